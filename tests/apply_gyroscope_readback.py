"""A triad's calibration file with a gyroscope section, written and read with Python's standard
library only (run as /usr/bin/python3 -I -S: no numpy, no site packages), as docs/calibration.md
tells a reader to: write the file by hand (the gyroscope in deg/s), apply it to a log with
gyroscope columns, read the corrected CSV with the csv module (skipping the '#' lines), and check
that the gyroscope's columns are finite numbers equal to w = T K (u - b) and to the sigma of
J C J^T computed here.

    apply_gyroscope_readback.py BIN_DIR
"""

import csv
import json
import math
import os
import subprocess
import sys
import tempfile

AXES = "xyz"
ANGLES = ["yz", "zy", "zx", "xz", "xy", "yx"]
GYROSCOPE_ORDER = ([f"gyroscope_misalignment_{a}" for a in ANGLES] +
                   [f"gyroscope_gain_{k}" for k in AXES] +
                   [f"gyroscope_offset_{k}" for k in AXES])


def check(condition, message):
    if not condition:
        sys.exit("FAIL: " + message)


def block(names, values, units, sigma, correlated_pairs):
    """parameter_order, parameters, units, stddev, covariance: sigma_i sigma_j rho_ij, rho 0.3
    for each pair given (disjoint pairs, so positive definite)."""
    n = len(names)
    covariance = [[0.0] * n for _ in range(n)]
    for i in range(n):
        covariance[i][i] = sigma[i] * sigma[i]
    for i, j in correlated_pairs:
        covariance[i][j] = covariance[j][i] = 0.3 * sigma[i] * sigma[j]
    return {
        "parameter_order": names,
        "parameters": dict(zip(names, values)),
        "units": dict(zip(names, units)),
        "stddev": {name: math.sqrt(covariance[i][i]) for i, name in enumerate(names)},
        "covariance": covariance,
    }


def calibration():
    triad_names = (["misalignment_yz", "misalignment_zy", "misalignment_zx"] +
                   [f"gain_{k}" for k in AXES] + [f"offset_{k}" for k in AXES])
    triad = block(triad_names,
                  [0.002, -0.001, 0.003, 1 / 415, 1.01 / 415, 0.99 / 415, 32808, 32743, 32778],
                  ["rad"] * 3 + ["(m/s^2)/count"] * 3 + ["count"] * 3,
                  [1e-4] * 3 + [1e-7] * 3 + [2.0] * 3, [(3, 6), (4, 7)])
    degree = math.pi / 180
    gyroscope = block(GYROSCOPE_ORDER,
                      [0.01, -0.02, 0.015, 0.005, -0.01, 0.02,
                       1.01 * degree, 0.99 * degree, 1.02 * degree, 0.5, -0.25, 0.125],
                      ["rad"] * 6 + ["(rad/s)/(deg/s)"] * 3 + ["deg/s"] * 3,
                      [1e-3] * 6 + [1e-3 * degree] * 3 + [0.05] * 3,
                      [(0, 1), (2, 5), (6, 9), (7, 10), (8, 11)])
    gyroscope.update({"output_unit": "deg/s", "fit": {"written_by": "a Python test"},
                      "model": {"measurement": "w = T K (u - b)"}})
    cal = {"format": "accelcal-calibration", "format_version": 1,
           "model": {"geometry": "triad", "output_unit": "count"},
           "gravity_mps2": 9.81,
           "noise_variance": {"x": 36.0, "y": 36.0, "z": 49.0, "unit": "(count)^2"},
           "gyroscope": gyroscope}
    cal.update(triad)
    return cal


def gyroscope_rate(p, u):
    """w = T K (u - b), docs/calibration.md's recipe, and its Jacobian (rows: axes; columns:
    GYROSCOPE_ORDER)."""
    yz, zy, zx, xz, xy, yx = (p[f"gyroscope_misalignment_{a}"] for a in ANGLES)
    t = [[1, -yz, zy], [xz, 1, -zx], [-xy, yx, 1]]
    gain = [p[f"gyroscope_gain_{k}"] for k in AXES]
    d = [u[k] - p[f"gyroscope_offset_{axis}"] for k, axis in enumerate(AXES)]
    along = [gain[k] * d[k] for k in range(3)]
    w = [sum(t[i][k] * along[k] for k in range(3)) for i in range(3)]
    jacobian = [[0.0] * 12 for _ in range(3)]
    # Each angle is one entry of T: (row, column, sign).
    for column, (row, k, sign) in enumerate([(0, 1, -1), (0, 2, 1), (1, 2, -1), (1, 0, 1),
                                             (2, 0, -1), (2, 1, 1)]):
        jacobian[row][column] = sign * along[k]
    for k in range(3):
        for i in range(3):
            jacobian[i][6 + k] = t[i][k] * d[k]
            jacobian[i][9 + k] = -t[i][k] * gain[k]
    return w, jacobian


def main():
    bin_dir = sys.argv[1]
    with tempfile.TemporaryDirectory() as scratch:
        cal = calibration()
        cal_path = os.path.join(scratch, "cal.json")
        with open(cal_path, "w") as f:
            json.dump(cal, f, indent=1)
        outputs = []
        log_path = os.path.join(scratch, "run.csv")
        with open(log_path, "w") as f:
            f.write("t_s,ax,ay,az,gx,gy,gz\n")
            for j in range(50):
                angle = 0.2 * j
                force = [9.81 * 0.6 * math.sin(angle), 9.81 * 0.6 * math.cos(angle), 9.81 * 0.8]
                acc = [offset + 415 * a for offset, a in zip((32808, 32743, 32778), force)]
                gyro = [0.5 + 90 * math.sin(0.7 * j), -0.25 + 200 * math.cos(0.3 * j),
                        0.125 - 350 * math.sin(0.11 * j + 0.2)]
                outputs.append(gyro)
                f.write(",".join(repr(v) for v in [0.01 * (j + 1)] + acc + gyro) + "\n")
        out = os.path.join(scratch, "corrected.csv")
        result = subprocess.run([os.path.join(bin_dir, "apply"), f"--calibration={cal_path}",
                                 f"--in={log_path}", f"--out={out}"], capture_output=True,
                                text=True)
        check(result.returncode == 0, f"apply failed ({result.returncode}): {result.stderr}")

        with open(cal_path) as f:
            section = json.load(f)["gyroscope"]
        p = section["parameters"]
        cov = section["covariance"]
        with open(out, newline="") as f:
            lines = f.read().splitlines()
        comments = [line for line in lines if line.startswith("#")]
        check(any("deg/s" in line and "not the gyroscope's white noise" in line
                  for line in comments), "the '#' line of the gyroscope")
        rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
        check(len(rows) == len(outputs), f"{len(rows)} rows for {len(outputs)} samples")
        names = ([f"g{k}_radps" for k in AXES] + [f"sigma_g{k}_radps" for k in AXES] +
                 ["corr_gxy", "corr_gxz", "corr_gyz"])
        for row, u in zip(rows, outputs):
            for name in names:
                check(name in row and row[name] not in (None, ""), f"column {name}")
                check(math.isfinite(float(row[name])), f"{name} = {row[name]} is not finite")
            w, jacobian = gyroscope_rate(p, u)
            variance = [[sum(jacobian[a][i] * cov[i][j] * jacobian[b][j]
                             for i in range(12) for j in range(12)) for b in range(3)]
                        for a in range(3)]
            for k, axis in enumerate(AXES):
                got = float(row[f"g{axis}_radps"])
                check(abs(got - w[k]) <= 1e-9 * max(1.0, abs(w[k])), f"g{axis} {got} != {w[k]}")
                sigma = math.sqrt(variance[k][k])
                got = float(row[f"sigma_g{axis}_radps"])
                check(abs(got - sigma) <= 1e-6 * sigma, f"sigma_g{axis} {got} != {sigma}")
            for (a, b), name in zip([(0, 1), (0, 2), (1, 2)], names[6:]):
                rho = variance[a][b] / math.sqrt(variance[a][a] * variance[b][b])
                check(abs(float(row[name]) - rho) <= 1e-6, f"{name} {row[name]} != {rho}")
        print(f"ok: {len(rows)} gyroscope samples of a hand-written section read back with the "
              "standard library")


main()
