#!/usr/bin/python3
"""Writes the bad-input corpus: small files, each wrong (or awkward) in one way a real
user's file can be. Run it from anywhere with Debian's /usr/bin/python3 (scipy.io writes
the MATLAB classes the project itself never writes: int32, single, complex, cell, struct;
version 7.3 files come from Debian's libmatio, built with HDF5, through ctypes). It also
writes the .mat fuzzer's seed sets tests/fuzz/seeds/mat_file/{compressed,v73}.
The outputs are committed; tests/data/bad/cases.txt says what each must produce.

    /usr/bin/python3 tests/data/bad/make_corpus.py
"""
import ctypes
import ctypes.util
import io
import os
import struct
import zlib

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


# --- MAT integrity (issue 15): damage that matio reads without an error ---
#
# A version 5 file is a 128-byte header and top-level elements, each an 8-byte tag (type,
# bytes) and its data; miCOMPRESSED (15) holds one zlib stream that inflates to a miMATRIX
# (14) element, its tag included, and MATLAB, SciPy and matio write nothing after the stream.

MI_MATRIX = 14
MI_COMPRESSED = 15


def mat5_bytes(variables, compressed):
    stream = io.BytesIO()
    scipy.io.savemat(stream, variables, format="5", oned_as="column", do_compression=compressed)
    return stream.getvalue()


def mat5_elements(data):
    """The header and the top-level elements (tag, data) of a version 5 file."""
    elements = []
    at = 128
    while at < len(data):
        kind, count = struct.unpack_from("<II", data, at)
        stored = count if kind == MI_COMPRESSED else (count + 7) // 8 * 8
        elements.append((kind, data[at + 8:at + 8 + stored]))
        at += 8 + stored
    return data[:128], elements


def mat5_join(header, elements):
    return header + b"".join(struct.pack("<II", kind, len(body)) + body for kind, body in elements)


def matrix_name(matrix):
    """The name of a miMATRIX element's bytes (tag included): array flags, dimensions, name."""
    at = 8 + 16
    _, dims_bytes = struct.unpack_from("<II", matrix, at)
    at += 8 + (dims_bytes + 7) // 8 * 8
    first, second = struct.unpack_from("<II", matrix, at)
    if first >> 16:  # the small form: 1-4 bytes packed with the tag
        return matrix[at + 4:at + 4 + (first >> 16)].decode()
    return matrix[at + 8:at + 8 + second].decode()


def damage_compressed(name, variables, victim, damage):
    """Saves `variables` compressed, then replaces the zlib stream of `victim` by
    damage(inflated), which returns the new stream."""
    header, elements = mat5_elements(mat5_bytes(variables, compressed=True))
    for k, (kind, body) in enumerate(elements):
        if kind == MI_COMPRESSED and matrix_name(zlib.decompress(body)) == victim:
            elements[k] = (kind, damage(zlib.decompress(body)))
    with open(path(name), "wb") as f:
        f.write(mat5_join(header, elements))


def inflates_short(inflated, fraction=0.001):
    """A complete zlib stream of the element less its last values (`fraction` of its bytes,
    at least one 8-byte value), the miMATRIX tag unchanged: matio fills the gap with zeros."""
    cut = max(8, int(len(inflated) * fraction) // 8 * 8)
    return zlib.compress(inflated[:-cut])


def stream_cut(inflated, kept=0.7):
    """The element's zlib stream cut at `kept` of its length, its miCOMPRESSED tag telling the
    truth about the cut: the file is whole, the stream is not."""
    stream = zlib.compress(inflated)
    return stream[: int(len(stream) * kept)]


def data_short(name, variables, victim, missing_values):
    """Saves `variables` uncompressed, then removes the last `missing_values` doubles of
    `victim`'s real data, with its data tag and its miMATRIX tag shortened to match: every
    length in the file agrees except the data's with the dimensions."""
    header, elements = mat5_elements(mat5_bytes(variables, compressed=False))
    for k, (kind, body) in enumerate(elements):
        if kind == MI_MATRIX and matrix_name(struct.pack("<II", kind, len(body)) + body) == victim:
            data_at = len(body)
            # The real data is the last subelement: find its tag from the front.
            at = 16
            while at < len(body):
                first, count = struct.unpack_from("<II", body, at)
                size = 8 if first >> 16 else 8 + (count + 7) // 8 * 8
                if at + size == len(body):
                    data_at = at
                at += size
            kind_of_data, count = struct.unpack_from("<II", body, data_at)
            assert kind_of_data == 9 and count % 8 == 0  # miDOUBLE
            count -= 8 * missing_values
            body = body[:data_at] + struct.pack("<II", kind_of_data, count) + \
                body[data_at + 8:data_at + 8 + count]
            elements[k] = (kind, body)
    with open(path(name), "wb") as f:
        f.write(mat5_join(header, elements))


def duplicate_variable(name, variables, repeated):
    """A file holding every variable of `variables` and then `repeated` (name: value) again,
    as two saves appended to one another would."""
    header, elements = mat5_elements(mat5_bytes(variables, compressed=False))
    _, more = mat5_elements(mat5_bytes(repeated, compressed=False))
    with open(path(name), "wb") as f:
        f.write(mat5_join(header, elements + more))


def save_v73(name, variables):
    """A version 7.3 (HDF5) file written by libmatio, which links HDF5 (Debian's does)."""
    lib = ctypes.CDLL(ctypes.util.find_library("matio"))
    lib.Mat_CreateVer.restype = ctypes.c_void_p
    lib.Mat_CreateVer.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_int]
    lib.Mat_VarCreate.restype = ctypes.c_void_p
    lib.Mat_VarCreate.argtypes = [ctypes.c_char_p, ctypes.c_int, ctypes.c_int, ctypes.c_int,
                                  ctypes.POINTER(ctypes.c_size_t), ctypes.c_void_p, ctypes.c_int]
    lib.Mat_VarWrite.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int]
    lib.Mat_VarFree.argtypes = [ctypes.c_void_p]
    lib.Mat_Close.argtypes = [ctypes.c_void_p]
    mat_ft_mat73, mat_c_double, mat_t_double = 0x0200, 6, 9
    if os.path.exists(path(name)):
        os.remove(path(name))
    # A fixed header text (matio's own records the time) keeps the file byte-identical.
    mat = lib.Mat_CreateVer(path(name).encode(),
                            b"MATLAB 7.3 MAT-file, Platform: accelcal corpus, "
                            b"Created on: Thu Jan  1 00:00:00 2026 HDF5 schema 1.00 .", mat_ft_mat73)
    assert mat, "libmatio cannot write version 7.3 files (built without HDF5?)"
    for variable, value in variables.items():
        value = np.asfortranarray(np.asarray(value, dtype=np.float64).reshape(len(value), -1))
        dims = (ctypes.c_size_t * 2)(*value.shape)
        var = lib.Mat_VarCreate(variable.encode(), mat_c_double, mat_t_double, 2, dims,
                                value.ctypes.data, 0)
        assert var and lib.Mat_VarWrite(mat, var, 0) == 0
        lib.Mat_VarFree(var)
    lib.Mat_Close(mat)
    fix_hdf5_times(name)


def fix_hdf5_times(name):
    """HDF5 stamps each dataset with its modification time (a version 1 message 0x12: type,
    size 8, flags, version 1, then the seconds); a fixed one keeps the file byte-identical."""
    with open(path(name), "rb") as f:
        data = bytearray(f.read())
    stamp = struct.pack("<HHB3xB3x", 0x12, 8, 0, 1)
    at = data.find(stamp)
    assert at > 0, "no modification time message in " + name
    while at > 0:
        struct.pack_into("<I", data, at + len(stamp), 1767225600)  # 2026-01-01 00:00:00 UTC
        at = data.find(stamp, at + 1)
    with open(path(name), "wb") as f:
        f.write(bytes(data))


def add_hdf5_attribute(name, dataset, attribute, values):
    """Adds an int32 attribute of `values` to `dataset` of an HDF5 file, through Debian's
    libhdf5 (the library libmatio links)."""
    hdf5 = ctypes.CDLL(ctypes.util.find_library("hdf5_serial") or "libhdf5_serial.so.103")
    hid_t, h5p_default = ctypes.c_int64, 0
    for function, result, arguments in [
            ("H5open", ctypes.c_int, []),
            ("H5Fopen", hid_t, [ctypes.c_char_p, ctypes.c_uint, hid_t]),
            ("H5Dopen2", hid_t, [hid_t, ctypes.c_char_p, hid_t]),
            ("H5Screate_simple", hid_t, [ctypes.c_int, ctypes.POINTER(ctypes.c_uint64), ctypes.c_void_p]),
            ("H5Acreate2", hid_t, [hid_t, ctypes.c_char_p, hid_t, hid_t, hid_t, hid_t]),
            ("H5Awrite", ctypes.c_int, [hid_t, hid_t, ctypes.c_void_p]),
            ("H5Aclose", ctypes.c_int, [hid_t]), ("H5Sclose", ctypes.c_int, [hid_t]),
            ("H5Dclose", ctypes.c_int, [hid_t]), ("H5Fclose", ctypes.c_int, [hid_t])]:
        getattr(hdf5, function).restype = result
        getattr(hdf5, function).argtypes = arguments
    assert hdf5.H5open() >= 0
    native_int = hid_t.in_dll(hdf5, "H5T_NATIVE_INT_g").value
    h5f_acc_rdwr = 1
    file = hdf5.H5Fopen(path(name).encode(), h5f_acc_rdwr, h5p_default)
    data = hdf5.H5Dopen2(file, dataset.encode(), h5p_default)
    count = (ctypes.c_uint64 * 1)(len(values))
    space = hdf5.H5Screate_simple(1, count, None)
    attr = hdf5.H5Acreate2(data, attribute.encode(), native_int, space, h5p_default, h5p_default)
    array = np.asarray(values, dtype=np.int32)
    assert min(file, data, space, attr) >= 0 and hdf5.H5Awrite(attr, native_int, array.ctypes.data) >= 0
    for close, handle in [(hdf5.H5Aclose, attr), (hdf5.H5Sclose, space), (hdf5.H5Dclose, data),
                          (hdf5.H5Fclose, file)]:
        close(handle)
    fix_hdf5_times(name)


def truncate(name, source, kept=0.6):
    with open(path(source), "rb") as f:
        whole = f.read()
    with open(path(name), "wb") as f:
        f.write(whole[: int(len(whole) * kept)])  # a copy interrupted at 60%


def fuzz_seeds():
    """Small valid files for the fuzzer's compressed-stream and version 7.3 paths:
    tests/fuzz/seeds/mat_file/compressed and tests/fuzz/seeds/mat_file/v73 (tools/fuzz.sh
    mat_file/compressed and mat_file/v73 fuzz from each set alone)."""
    seeds = os.path.join(HERE, "..", "..", "fuzz", "seeds", "mat_file")
    theta, datos = tilt_test(samples=16)
    t, aerr = run(samples=11)
    landmarks = {"A": np.array([[353.6, 73.2]]), "B": np.array([[592.5, 17.3]])}
    cell = np.empty((1, 2), dtype=object)
    cell[0, 0], cell[0, 1] = theta[:8], theta[8:]
    compressed = {
        "ensayo.mat": {"tita": theta, "datos": datos},
        "acel.mat": {"t": t, "Aerr": aerr},
        "puntos.mat": landmarks,
        # Nested elements, integer and complex data, in compressed streams.
        "ensayo_struct.mat": {"tita": theta.astype(np.uint8),
                              "datos": {"x": datos[:, 0], "y": datos[:, 1]}},
        "ensayo_cell_complex.mat": {"tita": cell, "datos": datos + 0.5j},
    }
    os.makedirs(os.path.join(seeds, "compressed"), exist_ok=True)
    for name, variables in compressed.items():
        with open(os.path.join(seeds, "compressed", name), "wb") as f:
            f.write(mat5_bytes(variables, compressed=True))
    os.makedirs(os.path.join(seeds, "v73"), exist_ok=True)
    for name, variables in {"ensayo.mat": {"tita": theta, "datos": datos},
                            "acel.mat": {"t": t, "Aerr": aerr}, "puntos.mat": landmarks}.items():
        save_v73(os.path.join("..", "..", "fuzz", "seeds", "mat_file", "v73", name), variables)


def mat_integrity():
    theta, datos = tilt_test()
    long_theta, long_datos = tilt_test(samples=500)
    t, aerr = run(samples=500)
    # Compressed (MATLAB's default, save -v7), complete zlib streams 0.1% short of what
    # their miMATRIX tags declare: matio returns the variable as zeros.
    damage_compressed("acel_inflates_short.mat", {"t": t, "Aerr": aerr}, "Aerr", inflates_short)
    damage_compressed("ensayo_inflates_short.mat", {"tita": long_theta, "datos": long_datos},
                      "datos", inflates_short)
    damage_compressed("ensayo_stream_cut.mat", {"tita": theta, "datos": datos}, "datos", stream_cut)
    data_short("ensayo_data_short.mat", {"tita": theta, "datos": datos}, "datos", 2)
    # Two saves appended (or a tool that writes one variable twice): MATLAB and SciPy read
    # the second tita, matio the first.
    duplicate_variable("ensayo_duplicate_name.mat", {"tita": theta, "datos": datos},
                       {"tita": theta[::-1].copy()})
    # Version 7.3 (save -v7.3, HDF5): one read whole, one copy interrupted at 60%.
    save_v73("ensayo_v73.mat", {"tita": theta, "datos": datos})
    truncate("ensayo_v73_truncated.mat", "ensayo_v73.mat")
    # A valid HDF5 file whose tita carries a MATLAB_global attribute of 4000 values: matio
    # reads it into one int and overwrites its own memory (the old reader crashed).
    save_v73("ensayo_v73_global_attribute.mat", {"tita": theta, "datos": datos})
    add_hdf5_attribute("ensayo_v73_global_attribute.mat", "tita", "MATLAB_global", [1] * 4000)


# --- readers (issue 15): inputs that do not say what they claim ---


def readers_issue_15():
    """Files the readers used to answer from, wrongly or silently (cases.txt, "readers")."""
    # A tilt test from 80 to 92 degrees, written in degrees: a span of 12, below the 4 pi that
    # the span check looks for, so only the physics tells (io/theta_agreement.h). With this
    # seed the former reader fitted it as radians without a word: scale_x = -0.999, exit 0.
    rng = np.random.default_rng(22)
    samples = 400
    theta = np.radians(np.linspace(80.0, 92.0, samples))
    ax = 0.08 + (1 - 0.03) * -G * np.sin(theta) + 0.5 * rng.standard_normal(samples)
    ay = -0.02 + (1 + 0.01) * -G * np.cos(theta) + 0.8 * rng.standard_normal(samples)
    csv("calibration_80_92_degrees.csv", "theta,ax,ay", number_rows(np.degrees(theta), ax, ay))
    save("ensayo_80_92_degrees.mat", {"tita": np.degrees(theta), "datos": np.column_stack([ax, ay])})

    # A copy cut short inside the last number, and a file whose name says CSV in capitals.
    full_theta, datos = tilt_test()
    rows = number_rows(full_theta, datos[:, 0], datos[:, 1])
    text = "theta,ax,ay\n" + "".join(",".join(row) + "\n" for row in rows)
    write_text("calibration_cut_short.csv", text[: text.rindex(".") + 2])
    csv("calibration_upper.CSV", "theta,ax,ay", rows)
    t, aerr = run()
    text = "t,ax,ay\n" + "".join(",".join(r) + "\n" for r in number_rows(t, aerr[:, 0], aerr[:, 1]))
    write_text("trajectory_cut_short.csv", text[: text.rindex(".") + 3])

    # A 100 Hz logger stamping Unix time (t ~ 1.7e9 s, where doubles resolve 2.4e-7 s), and the
    # same with samples 501 and 502 stamped 20 us late.
    stamps = ["%.2f" % (1.7e9 + 0.01 * j) for j in range(1000)]
    values = 0.5 * rng.standard_normal((1000, 2))
    cells = lambda j: "%r,%r\n" % (float(values[j, 0]), float(values[j, 1]))
    write_text("trajectory_unix_time.csv",
               "t,ax,ay\n" + "".join(stamps[j] + "," + cells(j) for j in range(1000)))
    late = list(stamps)
    for j in (500, 501):
        late[j] = "%.5f" % (1.7e9 + 0.01 * j + 2e-5)
    write_text("trajectory_unix_time_glitch.csv",
               "t,ax,ay\n" + "".join(late[j] + "," + cells(j) for j in range(1000)))

    # datos.txt with a final position (or velocity) where the initial one belongs.
    variance = "varianza del ruido de los acelerómetros = [0.25 0.64]\n"
    write_text("datos_final_position.txt",
               "Posición final = [459.84 59.99]\nVelocidad inicial = [1 3]\n" + variance)
    write_text("datos_final_velocity.txt",
               "Posición inicial = [0 0]\nVelocidad final = [2.1 0.4]\n" + variance)

    # JSON with a key given twice: nlohmann::json keeps the last value without a word.
    write_text("scenario_duplicate_key.json", """{
  "initial_position": [0, 0],
  "initial_velocity": [1, 3],
  "noise_variance": [0.25, 0.64],
  "noise_variance": [25, 64]
}
""")
    write_text("scenario_duplicate_nested.json", """{
  "name": "duplicate-dt",
  "gravity": 9.8,
  "noise_variance": [0.25, 0.64],
  "initial_position": [0, 0],
  "initial_velocity": [1, 3],
  "tilt": {"schedule": "uniform", "samples": 200, "from_rad": 0, "to_rad": 6.283185307179586},
  "run": {"dt": 0.01, "duration": 10, "dt": 0.1,
          "profile": {"segments": [{"duration": 10, "acceleration": [0.5, 0.0]}], "smoothing": 0}},
  "landmarks": {"listed": [{"name": "A", "position": [120, 45]}]}
}
""")

    # Cells a message must not echo whole: 100 kB of digits, and terminal escapes with a
    # Latin-1 byte (not UTF-8).
    bad = [list(r) for r in rows]
    bad[2][1] = "7" * 100000 + "x"
    csv("calibration_huge_cell.csv", "theta,ax,ay", bad)
    bad = [list(r) for r in rows]
    bad[3][2] = "\x1b[2J\x07\xe9-9.8"
    write_text("calibration_control_chars.csv",
               "theta,ax,ay\n" + "".join(",".join(r) + "\n" for r in bad), encoding="latin-1")
    write_text("landmarks_long_name.csv", "name,x,y\nA,1,2\n" + "B" * 10000 + ",3,4\n")


def conditions_and_landmarks_issue_15():
    """Statements that pass "positive" or "1x2" but are not what they claim (cases.txt)."""
    # Variances that overflow or underflow every covariance: NaN in path.csv and "posterior
    # -nan" on stdout before io/run_conditions.h bounded them.
    write_text("datos_variance_huge.txt", "Posición inicial = [0 0]\nVelocidad inicial = [1 3]\n"
               "varianza del ruido de los acelerómetros = [1e300 0.64]\n")
    write_text("datos_variance_denormal.txt", "Posición inicial = [0 0]\nVelocidad inicial = [1 3]\n"
               "varianza del ruido de los acelerómetros = [0.25 1e-320]\n")
    # puntos.mat saved with MATLAB's last unnamed result beside the landmarks.
    save("puntos_ans.mat", {"A": np.array([[120.0, 45.0]]), "B": np.array([[300.0, -20.0]]),
                            "ans": np.array([[0.25, 0.64]])})


def probe_findings_issue_15():
    """What an outside probe of the reliability work still found (cases.txt)."""
    rng = np.random.default_rng(15)
    # A tilt test at 0 and pi only: f_x = -g sin(theta) is 0 at both, so scale_x is whatever
    # the noise makes it (1.7e13 was reported, exit 0).
    theta = np.repeat([0.0, np.pi], 100)
    ax = 0.08 + 0.5 * rng.standard_normal(theta.size)
    ay = -0.02 + (1 + 0.01) * -G * np.cos(theta) + 0.8 * rng.standard_normal(theta.size)
    csv("calibration_two_angles_0_pi.csv", "theta,ax,ay", number_rows(theta, ax, ay))
    # The outputs of a plausible test in g and in mg instead of m/s^2.
    full_theta, datos = tilt_test()
    save("ensayo_in_g.mat", {"tita": full_theta, "datos": datos / G})
    save("ensayo_in_mg.mat", {"tita": full_theta, "datos": 1000.0 * datos / G})
    # A run whose time is in milliseconds, and one holding both names of the accelerations.
    t, aerr = run()
    save("acel_time_ms.mat", {"t": 1000.0 * t, "Aerr": aerr})
    save("acel_both_names.mat", {"t": t, "Aerr": aerr, "acel": np.zeros_like(aerr)})
    # A landmark name written in Latin-1, and a calibration CSV with old Mac line ends.
    write_text("landmarks_latin1_name.csv", "name,x,y\nA,120,45\n\u00d1and\u00fa,300,-20\n",
               encoding="latin-1")
    rows = number_rows(full_theta, datos[:, 0], datos[:, 1])
    write_text("calibration_cr_only.csv",
               "theta,ax,ay\r" + "".join(",".join(row) + "\r" for row in rows))
    write_text("datos_cr_only.txt", "Posición inicial = [0 0]\rVelocidad inicial = [1 3]\r"
               "varianza del ruido de los acelerómetros = [0.25 0.64]\r")


def calibration_files():
    """Calibration files (docs/calibration.md) as a user might damage or mistake them."""
    import json

    def cal(**changes):
        document = {
            "format": "accelcal-calibration", "format_version": 1,
            "model": {"geometry": "two_axis", "axes": ["x", "y"], "effects": ["bias", "scale"]},
            "gravity_mps2": 9.8,
            "parameter_order": ["bias_x", "scale_x", "bias_y", "scale_y"],
            "parameters": {"bias_x": 0.0767, "scale_x": -0.0301, "bias_y": -0.0175,
                           "scale_y": 0.01},
            "units": {"bias_x": "m/s^2", "scale_x": "1", "bias_y": "m/s^2", "scale_y": "1"},
            "covariance": [[1.25e-5, 0, 0, 0], [0, 2.6e-7, 0, 0], [0, 0, 3.2e-5, 3.3e-10],
                           [0, 0, 3.3e-10, 6.7e-7]],
            "noise_variance": {"x": 0.25, "y": 0.64, "unit": "(m/s^2)^2", "from": "datos.txt"},
        }
        for key, value in changes.items():
            document[key] = value
        return json.dumps(document, indent=1) + "\n"

    write_text("calibration_file_good.json", cal())
    write_text("calibration_file_mg.json",
               cal(units={"bias_x": "mg", "scale_x": "1", "bias_y": "mg", "scale_y": "1"},
                   parameters={"bias_x": 7.82, "scale_x": -0.0301, "bias_y": -1.78,
                               "scale_y": 0.01}))
    write_text("calibration_file_not_psd.json",
               cal(covariance=[[1.25e-5, 1e-5, 0, 0], [1e-5, 2.6e-7, 0, 0], [0, 0, 3.2e-5, 0],
                               [0, 0, 0, 6.7e-7]]))
    write_text("calibration_file_v2.json", cal(format_version=2))
    write_text("calibration_file_truncated.json", cal()[:300])
    # A linear_ls result (it has "parameters" too) given where a calibration belongs.
    write_text("calibration_file_linear_ls.json",
               json.dumps({"problem": "linear_ls", "parameters": {"bias_x": 0.0767}}) + "\n")



def calibration_fuzz_seeds():
    """Seeds of the calibration file's fuzz target (tests/fuzz/seeds/calibration_file): a
    two-axis file, the triad's (triad_gyroscope.json, written by calibrate_imu --mode=ml on
    imu_tk's Xsens pair, the seeds README says how; with and without its gyroscope section), and
    the same nested deep (issue 35: a file nested thousands of levels crashed apply) or made
    large, each under the fuzzer's 64 KB."""
    import copy
    import json
    import sys

    sys.setrecursionlimit(100000)  # json.dumps recurses once per level of the deepest seed
    seeds = os.path.join(HERE, "..", "..", "fuzz", "seeds", "calibration_file")
    with open(os.path.join(seeds, "triad_gyroscope.json")) as f:
        triad = json.load(f)

    def write(name, document, indent=None):
        # The deep and large ones compact: indentation would only add bytes.
        text = document if isinstance(document, str) else json.dumps(
            document, indent=indent, separators=None if indent else (",", ":")) + "\n"
        assert len(text) < 65536, name
        with open(os.path.join(seeds, name), "w") as f:
            f.write(text)

    def nested(depth, leaf=0):
        value = leaf
        for _ in range(depth):
            value = [value]
        return value

    def with_changes(document, **changes):
        changed = copy.deepcopy(document)
        for key, value in changes.items():
            changed[key] = value
        return changed

    sigma = [1.25e-5 ** 0.5, 2.6e-7 ** 0.5, 3.2e-5 ** 0.5, 6.7e-7 ** 0.5]
    names = ["bias_x", "scale_x", "bias_y", "scale_y"]
    two_axis = {
        "format": "accelcal-calibration", "format_version": 1,
        "model": {"geometry": "two_axis", "axes": ["x", "y"], "effects": ["bias", "scale"],
                  "output_unit": "m/s^2",
                  "measurement": "m_k = (1 + scale_k) a_k + bias_k + noise_k, k = x, y"},
        "gravity_mps2": 9.8,
        "parameter_order": names,
        "parameters": {"bias_x": 0.0767, "scale_x": -0.0301, "bias_y": -0.0175, "scale_y": 0.01},
        "units": {"bias_x": "m/s^2", "scale_x": "1", "bias_y": "m/s^2", "scale_y": "1"},
        "stddev": dict(zip(names, sigma)),
        "covariance": [[1.25e-5, 0, 0, 0], [0, 2.6e-7, 0, 0], [0, 0, 3.2e-5, 0],
                       [0, 0, 0, 6.7e-7]],
        "noise_variance": {"x": 0.25, "y": 0.64, "unit": "(m/s^2)^2", "from": "datos.txt"},
        "fit": {"samples": 400}, "poorly_determined": None, "gyroscope": None,
    }
    write("two_axis.json", two_axis, indent=1)
    write("triad.json", with_changes(triad, gyroscope=None), indent=1)
    # Depth: the reader's limit is 64 levels (io/json_file.h); the file's own object is one.
    write("deep_fit_63.json", with_changes(two_axis, fit=nested(63)))
    write("deep_fit_64.json", with_changes(two_axis, fit=nested(64)))
    write("deep_model_200.json", with_changes(two_axis, model=nested(200)))
    gyroscope = copy.deepcopy(triad["gyroscope"])
    gyroscope["fit"] = {"turns": nested(300)}
    write("deep_gyroscope_fit_300.json", with_changes(triad, gyroscope=gyroscope))
    # Inside a key the reader copies (fit), as deep as 64 KB holds: what crashed apply.
    write("deep_fit_30000.json", with_changes(two_axis, fit=nested(30000)))
    write("deep_brackets_20000.json", "[" * 20000)
    write("deep_objects_2000.json", '{"fit":' * 2000 + "1" + "}" * 2000)
    # Size: long lists, long rows, long strings and numbers, many keys.
    write("large_parameter_order.json",
          with_changes(two_axis, parameter_order=["bias_x%d" % i for i in range(1000)]))
    write("large_covariance_rows.json",
          with_changes(two_axis, covariance=[[0.0] * 1000 for _ in range(4)]))
    write("large_string.json", with_changes(two_axis, created_utc="x" * 20000))
    write("large_number.json", json.dumps(two_axis, indent=1).replace(
        '"bias_x": 0.0767', '"bias_x": ' + "9" * 10000, 1))
    write("large_exponent.json", json.dumps(two_axis, indent=1).replace(
        "1.25e-05", "1e999", 1))
    write("many_keys.json", with_changes(two_axis, fit={"k%d" % i: i for i in range(1500)}))
    write("large_poorly_determined.json", with_changes(
        triad, poorly_determined=[{"parameter": "gain_x"}] * 600))


def host_time_bursts_issue_44():
    """A BLE logger's CSV: host receive times in microseconds, the samples delivered in bursts
    of 2 to 8 (0.2 ms apart, after the burst's last sample), no sample-number column."""
    rng = np.random.default_rng(44)
    rows, first = [], 0
    while first < 300:
        last = min(299, first + int(rng.integers(2, 9)) - 1)
        delivered_us = 1_000_000 + last * 10_000 + int(rng.integers(100, 3000))
        for position, _ in enumerate(range(first, last + 1)):
            rows.append([str(delivered_us + 200 * position), "%.4f" % rng.normal(0.0, 0.01),
                         "%.4f" % rng.normal(0.0, 0.01), "%.4f" % rng.normal(G, 0.01)])
        first = last + 1
    csv("imu_host_bursts.csv", "t_us,ax,ay,az", rows)


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

    mat_integrity()
    fuzz_seeds()
    calibration_fuzz_seeds()
    calibration_files()
    host_time_bursts_issue_44()
    readers_issue_15()
    conditions_and_landmarks_issue_15()
    probe_findings_issue_15()


if __name__ == "__main__":
    main()
