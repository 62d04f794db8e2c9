#!/usr/bin/python3
"""Writes the bad-input corpus: small files, each wrong (or awkward) in one way a real
user's file can be. Run it from anywhere with Debian's /usr/bin/python3 (scipy.io writes
the MATLAB classes the project itself never writes: int32, single, complex, cell, struct).
The outputs are committed; tests/data/bad/cases.txt says what each must produce.

    /usr/bin/python3 tests/data/bad/make_corpus.py
"""
import os
import struct

import numpy as np
import scipy.io
import scipy.io.matlab._mio5

# The MAT header records when the file was made; a fixed date keeps regenerated files
# byte-identical, so a re-run shows no change unless the corpus itself changed.
scipy.io.matlab._mio5.time.asctime = lambda *args: "Thu Jan  1 00:00:00 2026"

HERE = os.path.dirname(os.path.abspath(__file__))
G = 9.8


def path(name):
    return os.path.join(HERE, name)


def tilt_test(samples=40, seed=1):
    """A plausible tilt test: biases, scale errors and noise, theta over one turn (rad)."""
    rng = np.random.default_rng(seed)
    theta = np.linspace(0.0, 2.0 * np.pi, samples, endpoint=False)
    # The spec's specific force: f_x = -g sin(theta), f_y = -g cos(theta).
    ax = 0.08 + (1 - 0.03) * -G * np.sin(theta) + 0.5 * rng.standard_normal(samples)
    ay = -0.02 + (1 + 0.01) * -G * np.cos(theta) + 0.8 * rng.standard_normal(samples)
    return theta, np.column_stack([ax, ay])


def run(samples=50, dt=0.01, seed=2):
    rng = np.random.default_rng(seed)
    t = dt * np.arange(samples)
    return t, 0.5 * rng.standard_normal((samples, 2))


def save(name, variables):
    scipy.io.savemat(path(name), variables, format="5", oned_as="column")


def write_text(name, text, encoding="utf-8"):
    with open(path(name), "wb") as f:
        f.write(text.encode(encoding))


def csv(name, header, rows):
    write_text(name, header + "\n" + "".join(",".join(row) + "\n" for row in rows))


def number_rows(*columns):
    return [[repr(float(v)) for v in values] for values in zip(*columns)]


def main():
    theta, datos = tilt_test()

    # --- ensayo.mat (the tilt test) ---
    save("ensayo_truncated.mat", {"tita": theta, "datos": datos})
    with open(path("ensayo_truncated.mat"), "rb") as f:
        whole = f.read()
    with open(path("ensayo_truncated.mat"), "wb") as f:
        f.write(whole[: int(len(whole) * 0.6)])  # a copy interrupted at 60%
    write_text("ensayo_empty.mat", "")
    write_text("ensayo_text.mat", "tita = [0 1 2]\ndatos = [1 2; 3 4; 5 6]\n")
    scipy.io.savemat(path("ensayo_compressed.mat"), {"tita": theta, "datos": datos},
                     format="5", oned_as="column", do_compression=True)
    save("ensayo_transposed.mat", {"tita": theta, "datos": datos.T})
    save("ensayo_three_columns.mat", {"tita": theta, "datos": np.column_stack([datos, datos[:, 0]])})
    save("ensayo_int32.mat", {"tita": np.round(theta * 1000).astype(np.int32), "datos": datos})
    save("ensayo_single.mat", {"tita": theta.astype(np.float32), "datos": datos.astype(np.float32)})
    save("ensayo_complex.mat", {"tita": theta, "datos": datos + 0.5j})
    cell = np.empty((1, 2), dtype=object)
    cell[0, 0], cell[0, 1] = theta[:20], theta[20:]
    save("ensayo_cell.mat", {"tita": cell, "datos": datos})
    save("ensayo_struct.mat", {"tita": theta, "datos": {"x": datos[:, 0], "y": datos[:, 1]}})
    save("ensayo_empty_arrays.mat", {"tita": np.zeros((0, 1)), "datos": np.zeros((0, 2))})
    save("ensayo_wrong_names.mat", {"theta": theta, "data": datos})
    nan = datos.copy()
    nan[6, 1] = np.nan
    save("ensayo_nan.mat", {"tita": theta, "datos": nan})
    save("ensayo_degrees.mat", {"tita": np.degrees(theta), "datos": datos})
    two = np.where(np.arange(len(theta)) < len(theta) // 2, 0.5, 2.0)
    save("ensayo_two_positions.mat",
         {"tita": two, "datos": np.column_stack([-G * np.sin(two), -G * np.cos(two)])})
    save("ensayo_one_angle.mat", {"tita": np.full_like(theta, 0.3), "datos": datos})

    # A header that claims 10^9 rows for tita in a 1 kB file: its dimensions are the
    # first two int32 after the array-flags subelement (MAT-file format, v5).
    save("ensayo_huge_claim.mat", {"tita": theta, "datos": datos})
    with open(path("ensayo_huge_claim.mat"), "rb") as f:
        data = bytearray(f.read())
    dims_tag = struct.pack("<II", 5, 8)  # miINT32, 8 bytes: [rows cols]
    at = data.index(dims_tag, 128) + 8
    assert struct.unpack_from("<ii", data, at) == (len(theta), 1)
    struct.pack_into("<i", data, at, 10**9)
    with open(path("ensayo_huge_claim.mat"), "wb") as f:
        f.write(bytes(data))

    # Version 4 (Octave's save -v4): read as it is; a corrupted header is refused before matio
    # allocates what it declares (mat_file_fuzzer's fourth finding).
    scipy.io.savemat(path("ensayo_v4.mat"), {"tita": theta, "datos": datos}, format="4",
                     oned_as="column")
    with open(path("ensayo_v4.mat"), "rb") as f:
        v4 = f.read()
    # The first matrix's header: type, mrows, ncols, imagf, namlen (int32, little endian).
    assert struct.unpack_from("<5i", v4, 0)[1:] == (len(theta), 1, 0, len("tita") + 1)
    with open(path("ensayo_v4_huge_name.mat"), "wb") as f:
        f.write(v4[:16] + struct.pack("<i", 1413565728) + v4[20:])
    with open(path("ensayo_v4_huge_claim.mat"), "wb") as f:
        f.write(v4[:4] + struct.pack("<i", 10**9) + v4[8:])
    with open(path("ensayo_v4_truncated.mat"), "wb") as f:
        f.write(v4[: int(len(v4) * 0.6)])  # a copy interrupted at 60%

    # --- calibration.csv ---
    rows = number_rows(theta, datos[:, 0], datos[:, 1])
    csv("calibration_missing_column.csv", "theta,ax", [r[:2] for r in rows])
    csv("calibration_extra_column.csv", "theta,ax,ay,az", [r + ["9.8"] for r in rows])
    csv("calibration_short_row.csv", "theta,ax,ay", rows[:5] + [rows[5][:2]] + rows[6:])
    csv("calibration_header_only.csv", "theta,ax,ay", [])
    comma = [[v.replace(".", ",") for v in r] for r in rows]
    csv("calibration_decimal_comma.csv", "theta,ax,ay", comma)
    write_text("calibration_semicolons.csv",
               "theta;ax;ay\n" + "".join(";".join(r) + "\n" for r in comma))
    csv("calibration_nan.csv", "theta,ax,ay", rows[:8] + [[rows[8][0], rows[8][1], "NaN"]] + rows[9:])
    csv("calibration_inf.csv", "theta,ax,ay", rows[:3] + [[rows[3][0], "-inf", rows[3][2]]] + rows[4:])
    csv("calibration_non_numeric.csv", "theta,ax,ay",
        rows[:2] + [[rows[2][0], "abc", rows[2][2]]] + rows[3:])
    save("ensayo_inverted_axis.mat", {"tita": theta, "datos": datos * [-1, 1]})
    csv("calibration_degrees.csv", "theta,ax,ay", number_rows(np.degrees(theta), datos[:, 0], datos[:, 1]))

    # --- acel.mat / trajectory.csv (the run) ---
    t, aerr = run()
    save("acel_transposed.mat", {"t": t, "Aerr": aerr.T})
    repeated = t.copy()
    repeated[20] = repeated[19]
    save("acel_not_increasing.mat", {"t": repeated, "Aerr": aerr})
    gap = t.copy()
    gap[30:] += 0.01  # one sample lost
    save("acel_not_uniform.mat", {"t": gap, "Aerr": aerr})
    save("acel_single_sample.mat", {"t": t[:1], "Aerr": aerr[:1]})
    csv("trajectory_not_uniform.csv", "t,ax,ay", number_rows(gap, aerr[:, 0], aerr[:, 1]))
    backwards = t[::-1].copy()
    csv("trajectory_not_increasing.csv", "t,ax,ay", number_rows(backwards, aerr[:, 0], aerr[:, 1]))

    # --- puntos.mat / landmarks.csv ---
    save("puntos_identical.mat", {name: np.array([[120.0, 45.0]]) for name in "ABCD"})
    save("puntos_no_variables.mat", {})
    save("puntos_column.mat", {"A": np.array([[1.0], [2.0]]), "B": np.array([[3.0, 4.0]])})
    # The course's landmarks and one 10^4 km away: a typo in the units or a sign.
    far = {"A": [[353.6, 73.2]], "B": [[592.5, 17.3]], "C": [[459.8, 60.0]], "Far": [[1e7, -1e7]]}
    save("puntos_far.mat", {name: np.array(xy) for name, xy in far.items()})
    write_text("landmarks_identical.csv", "name,x,y\nA,120,45\nB,120,45\nC,120,45\n")
    write_text("landmarks_empty_name.csv", "name,x,y\nA,1,2\n,3,4\n")

    # --- datos.txt (the run's conditions) ---
    write_text("datos_missing_key.txt", "Posición inicial = [0 0]\nVelocidad inicial = [1 3]\n")
    write_text("datos_unbalanced.txt",
               "Posición inicial = [0 0\nVelocidad inicial = [1 3]\n"
               "varianza del ruido de los acelerómetros = [0.25 0.64]\n")
    write_text("datos_one_value.txt",
               "Posición inicial = [0 0]\nVelocidad inicial = [1]\n"
               "varianza del ruido de los acelerómetros = [0.25 0.64]\n")
    write_text("datos_latin1.txt",
               "Posición inicial = [0 0]\r\nVelocidad inicial = [1 3]\r\n"
               "varianza del ruido de los acelerómetros = [0.25 0.64]", encoding="latin-1")
    write_text("datos_negative_variance.txt",
               "Posición inicial = [0 0]\nVelocidad inicial = [1 3]\n"
               "varianza del ruido de los acelerómetros = [0.25 -0.64]\n")
    write_text("datos_empty.txt", "")

    # --- scenario.json ---
    write_text("scenario_identical_landmarks.json", """{
  "name": "identical-landmarks",
  "gravity": 9.8,
  "noise_variance": [0.25, 0.64],
  "initial_position": [0, 0],
  "initial_velocity": [1, 3],
  "tilt": {"schedule": "uniform", "samples": 200, "from_rad": 0, "to_rad": 6.283185307179586},
  "run": {"dt": 0.01, "duration": 10,
          "profile": {"segments": [{"duration": 10, "acceleration": [0.5, 0.0]}], "smoothing": 0}},
  "landmarks": {"listed": [
    {"name": "A", "position": [120, 45]},
    {"name": "B", "position": [120, 45]}
  ]},
  "truth": {"bias_x": 0.07667, "scale_x": -0.03014, "bias_y": -0.01751, "scale_y": 0.01004}
}
""")


if __name__ == "__main__":
    main()
