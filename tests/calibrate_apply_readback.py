"""A user's first session, checked with Python's standard library only (run as
/usr/bin/python3 -I -S, so no numpy, no site packages): simulate a tilt test and a run in the
CSV layout, calibrate from the tilt test, apply the calibration to the run, then read both
files back and recompute what they claim (issue 18).

    calibrate_apply_readback.py BIN_DIR
"""

import csv
import hashlib
import json
import math
import os
import subprocess
import sys
import tempfile


def run(binary, *arguments):
    result = subprocess.run([os.path.join(BIN_DIR, binary), *arguments],
                            capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{binary} failed ({result.returncode}): {result.stderr}")
    return result.stdout


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def check(condition, message):
    if not condition:
        sys.exit("FAIL: " + message)


def read_calibration(path, tilt_csv, truth):
    with open(path) as f:
        cal = json.load(f)
    check(cal["format"] == "accelcal-calibration" and cal["format_version"] == 1, "format")
    names = cal["parameter_order"]
    check(names == ["bias_x", "scale_x", "bias_y", "scale_y"], f"parameter_order {names}")
    check(cal["units"] == {"bias_x": "m/s^2", "scale_x": "1", "bias_y": "m/s^2", "scale_y": "1"},
          f"units {cal['units']}")
    cov = cal["covariance"]
    for i, name in enumerate(names):
        sigma = math.sqrt(cov[i][i])
        check(abs(cal["stddev"][name] - sigma) <= 1e-12 * sigma, f"stddev of {name}")
        z = (cal["parameters"][name] - truth["parameters"][name]) / sigma
        check(abs(z) < 4, f"{name} is {z:.2f} sigma from the truth")
        for j in range(len(names)):
            check(cov[i][j] == cov[j][i], "covariance symmetric")
    check(cal["input_files"]["calibration"]["sha256"] == sha256(tilt_csv), "tilt test checksum")
    check(cal["noise_variance"]["x"] == truth["stated_noise_variance"]["x"], "stated noise x")
    check(cal["source"]["kind"] == "measured", "source kind")
    return cal


def check_corrected(corrected_csv, run_csv, cal, cal_path):
    with open(corrected_csv) as f:
        lines = f.read().splitlines()
    comments = [line for line in lines if line.startswith("#")]
    check(any(sha256(cal_path) in line for line in comments), "calibration checksum in header")
    check(any(sha256(run_csv) in line for line in comments), "log checksum in header")
    rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
    with open(run_csv) as f:
        measured = list(csv.DictReader(f))
    check(len(rows) == len(measured) > 100, f"{len(rows)} rows for {len(measured)} samples")
    p = cal["parameters"]
    cov = cal["covariance"]
    for row, m in zip(rows, measured):
        check(float(row["t_s"]) == float(m["t"]), "time copied")
        jacobian = []
        for axis, (b, s) in (("x", ("bias_x", "scale_x")), ("y", ("bias_y", "scale_y"))):
            gain = 1 + p[s]
            a = (float(m["a" + axis]) - p[b]) / gain
            got = float(row[f"a{axis}_mps2"])
            check(abs(got - a) <= 1e-12 * max(1.0, abs(a)), f"a{axis} {got} != {a}")
            jacobian.append({b: -1 / gain, s: -a / gain})
        names = cal["parameter_order"]
        variance = [sum(jacobian[k].get(names[i], 0) * cov[i][j] * jacobian[k].get(names[j], 0)
                        for i in range(4) for j in range(4)) for k in range(2)]
        for k, axis in enumerate("xy"):
            got = float(row[f"sigma_a{axis}_mps2"])
            check(abs(got - math.sqrt(variance[k])) <= 1e-5 * got, f"sigma_a{axis}")
    return len(rows)


BIN_DIR = sys.argv[1]
with tempfile.TemporaryDirectory() as scratch:
    data = os.path.join(scratch, "sim")
    run("simulate", "--format=csv", f"--out_dir={data}", "--seed=5")
    with open(os.path.join(data, "truth.json")) as f:
        truth = json.load(f)
    cal_path = os.path.join(scratch, "cal.json")
    run("calibrate", f"--data_dir={data}", f"--calibration_out={cal_path}")
    cal = read_calibration(cal_path, os.path.join(data, "calibration.csv"), truth)
    corrected = os.path.join(scratch, "corrected.csv")
    run_csv = os.path.join(data, "trajectory.csv")
    run("apply", f"--calibration={cal_path}", f"--in={run_csv}", f"--out={corrected}")
    rows = check_corrected(corrected, run_csv, cal, cal_path)
    print(f"ok: calibration and {rows} corrected samples read back with the standard library")
