"""export_calibration's three exports read back by each format's own conventions (issue 34, item 3;
docs/calibration.md, "Exports"), from a real calibration: calibrate_imu --mode=ml on imu_tk's
Xsens session (accelerometer and gyroscope), allan on its two logs' rest, then

  imu_tk  PREFIX_acc.calib, PREFIX_gyro.calib read as CalibratedTriad_::load reads them (the first
          21 whitespace-separated numbers: T row-major, K row-major, b) and applied as its
          unbiasNormalize, T K (u - b);
  imucal  the JSON read as CalibrationInfo.from_json_file does (its keys are exactly
          FerrarisCalibrationInfo's fields plus cal_type and _format_version, the arrays made numpy
          arrays) and applied as FerrarisCalibrationInfo.calibrate: acc = R_a^-1 K_a^-1 (u - b_a),
          gyr = R_g^-1 K_g^-1 (u_g - K_ga acc - b_g), in deg/s;
  kalibr  imu.yaml read with yaml.safe_load and checked as Kalibr's ImuParameters does (positive
          terms, a string topic), each term against the Allan fits carried through the
          calibration's matrices here;

each applied to the whole session and compared with apply's corrected columns to 1e-9 of the
sample's magnitude. Each comparison is also run on a deliberately broken copy of its export (one
misalignment's sign flipped, R_a transposed, a term halved), which must fail, so that the checks
can fail.

    export_readback.py BIN_DIR IMU_TK_DATA_DIR      (python3 with numpy and yaml)
"""

import csv
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import yaml

TOLERANCE = 1e-9


def fail(message):
    sys.exit("FAIL: " + message)


def run(binary, *arguments):
    result = subprocess.run([binary, *arguments], capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"{os.path.basename(binary)} {' '.join(arguments)} exited {result.returncode}: "
             f"{result.stderr.strip()}")
    return result.stdout


def read_corrected(path):
    rows = list(csv.DictReader(line for line in open(path) if not line.startswith("#")))
    acc = np.array([[float(r[k]) for k in ("ax_mps2", "ay_mps2", "az_mps2")] for r in rows])
    gyr = np.array([[float(r[k]) for k in ("gx_radps", "gy_radps", "gz_radps")] for r in rows])
    return acc, gyr


def read_log(path):
    rows = list(csv.DictReader(open(path)))
    acc = np.array([[float(r[k]) for k in ("ax", "ay", "az")] for r in rows])
    gyr = np.array([[float(r[k]) for k in ("gx", "gy", "gz")] for r in rows])
    return acc, gyr


def worst(actual, expected):
    """The largest |actual - expected| over a sample's magnitude |expected|."""
    scale = np.linalg.norm(expected, axis=1)
    return float(np.max(np.abs(actual - expected).max(axis=1) / scale))


# imu_tk ----------------------------------------------------------------------------------------
def imu_tk_load(text):
    """CalibratedTriad_::load: `file >> mat[i]` 9 + 9 + 3 times; anything after is never read."""
    numbers = [float(token) for token in text.split()[:21]]
    if len(numbers) != 21:
        fail("an imu_tk .calib with fewer than 21 numbers")
    return (np.array(numbers[0:9]).reshape(3, 3), np.array(numbers[9:18]).reshape(3, 3),
            np.array(numbers[18:21]))


def imu_tk_apply(text, raw):
    misalignment, scale, bias = imu_tk_load(text)
    return (misalignment @ scale @ (raw - bias).T).T  # unbiasNormalize: ms_mat_ (X - B)


# imucal ----------------------------------------------------------------------------------------
FERRARIS_FIELDS = ["acc_unit", "gyr_unit", "from_acc_unit", "from_gyr_unit", "comment", "K_a",
                   "R_a", "b_a", "K_g", "R_g", "K_ga", "b_g"]
CAL_PARAS = ["K_a", "R_a", "b_a", "K_g", "R_g", "K_ga", "b_g"]


def imucal_load(text):
    raw = json.loads(text)
    # check_cal_format_version: packaging's Version must equal 2.0.0 ("2.0" does).
    version = raw.pop("_format_version", None)
    parts = [int(p) for p in version.split(".")] if isinstance(version, str) else []
    if (parts + [0, 0, 0])[:3] != [2, 0, 0] or len(parts) > 3:
        fail(f"imucal's _format_version is {version!r}, not 2.0.0")
    if raw.pop("cal_type", None) != "Ferraris":
        fail("imucal's cal_type is not Ferraris")
    # FerrarisCalibrationInfo(**list_dict): a key that is not a field is a TypeError.
    if sorted(raw) != sorted(FERRARIS_FIELDS):
        fail(f"imucal's keys {sorted(raw)} are not FerrarisCalibrationInfo's fields")
    for key in CAL_PARAS:
        raw[key] = np.array(raw[key])
    return raw


def imucal_apply(text, acc, gyr, acc_unit, gyr_unit):
    info = imucal_load(text)
    # CalibrationInfo._validate_units
    if acc_unit != info["from_acc_unit"] or gyr_unit != info["from_gyr_unit"]:
        fail(f"imucal's from units {info['from_acc_unit']}, {info['from_gyr_unit']} are not "
             f"{acc_unit}, {gyr_unit}")
    acc_out = (np.linalg.inv(info["R_a"]) @ np.linalg.inv(info["K_a"]) @ (acc - info["b_a"]).T).T
    offsets = (info["K_ga"] @ acc_out.T).T + info["b_g"]
    gyr_out = (np.linalg.inv(info["R_g"]) @ np.linalg.inv(info["K_g"]) @ (gyr - offsets).T).T
    return acc_out, gyr_out, info


# kalibr ----------------------------------------------------------------------------------------
def triad_matrix(p):
    t = np.array([[1, -p["misalignment_yz"], p["misalignment_zy"]],
                  [0, 1, -p["misalignment_zx"]],
                  [0, 0, 1]])
    return t @ np.diag([p["gain_" + k] for k in "xyz"])


def gyroscope_matrix(p):
    a = {n: p["gyroscope_misalignment_" + n] for n in ("yz", "zy", "zx", "xz", "xy", "yx")}
    t = np.array([[1, -a["yz"], a["zy"]], [a["xz"], 1, -a["zx"]], [-a["xy"], a["yx"], 1]])
    return t @ np.diag([p["gyroscope_gain_" + k] for k in "xyz"])


def allan_terms(allan):
    """Per output axis, in the log's unit: N, and K (or its bound from the curve)."""
    white, walk = [], []
    for axis in "xyz":
        a = allan["axes"][axis]
        white.append(a["white_noise"]["value"] / allan["gain"])
        if a["random_walk"]["resolved"]:
            walk.append(a["random_walk"]["value"] / allan["gain"])
        else:
            walk.append(min(math.sqrt(3 / p["tau_s"]) * p["adev_high"] for p in a["points"]) /
                        allan["gain"])
    return np.array(white), np.array(walk)


def kalibr_expected(calibration, allan_acc, allan_gyr):
    expected = {}
    for prefix, matrix, allan in (
            ("accelerometer", triad_matrix(calibration["parameters"]), allan_acc),
            ("gyroscope", gyroscope_matrix(calibration["gyroscope"]["parameters"]), allan_gyr)):
        white, walk = allan_terms(allan)
        expected[prefix + "_noise_density"] = float(np.max(np.sqrt(matrix**2 @ white**2)))
        expected[prefix + "_random_walk"] = float(np.max(np.sqrt(matrix**2 @ walk**2)))
    expected["update_rate"] = 1 / allan_acc["sample_period_s"]
    return expected


def kalibr_check(text, expected):
    """Kalibr's ImuParameters accessors, and each term against `expected`; the worst relative
    difference."""
    data = yaml.safe_load(text)
    if not isinstance(data.get("rostopic"), str):
        fail("Kalibr: rostopic has to be a string")
    worst_difference = 0.0
    for key, value in expected.items():
        if not isinstance(data.get(key), float) or not data[key] > 0:
            fail(f"Kalibr: invalid {key}: {data.get(key)!r}")
        worst_difference = max(worst_difference, abs(data[key] - value) / value)
    return worst_difference


def baseline_of(block):
    """`block` (the file's top level or its gyroscope section) with its baseline in place of
    the model with effect terms."""
    if block.get("baseline") is None:
        return block
    block = dict(block)
    for key in ("parameter_order", "parameters", "units", "stddev", "covariance"):
        block[key] = block["baseline"][key]
    block["baseline"] = None
    model = dict(block["model"])
    model.pop("effect_terms", None)
    model.pop("measurement_with_effects", None)
    if "effects" in model:
        model["effects"] = [e for e in model["effects"]
                            if e in ("misalignment", "gain", "offset")] or None
        if model["effects"] is None:
            del model["effects"]
    block["model"] = model
    return block


def without_terms(calibration):
    """A version-1 file of the calibration's baselines."""
    out = baseline_of(calibration)
    out["format_version"] = 1
    if out.get("gyroscope") is not None:
        out["gyroscope"] = baseline_of(out["gyroscope"])
    return out


def main():
    bin_dir, data_dir = sys.argv[1], sys.argv[2]
    binary = lambda name: os.path.join(bin_dir, name)
    with tempfile.TemporaryDirectory() as work:
        path = lambda name: os.path.join(work, name)
        # imu_tk's pair of ASCII files (t x y z, shared stamps) as one CSV with both sensors.
        acc_lines = open(os.path.join(data_dir, "xsens_acc.mat")).read().split("\n")
        gyr_lines = open(os.path.join(data_dir, "xsens_gyro.mat")).read().split("\n")
        with open(path("xsens.csv"), "w") as out:
            out.write("t,ax,ay,az,gx,gy,gz\n")
            for a, g in zip(acc_lines, gyr_lines):
                if a.strip():
                    a, g = a.split(), g.split()
                    assert a[0] == g[0]
                    out.write(",".join(a + g[1:]) + "\n")
        run(binary("calibrate_imu"), "--log=" + path("xsens.csv"), "--g=9.81744", "--mode=ml",
            "--initial_gyro_gain=0.000159795", "--calibration_out=" + path("cal.json"))
        for sensor, log in (("acc", "xsens_acc.mat"), ("gyro", "xsens_gyro.mat")):
            run(binary("allan"), "--log=" + os.path.join(data_dir, log), "--unit=count",
                "--static=longest", "--bootstrap=100", f"--json={path(sensor + '_allan.json')}")
        calibration = json.load(open(path("cal.json")))
        # A model with effect terms (format_version 2: the gyroscope's g-sensitivity on this
        # session) is exported as its baseline, the same session's fit without them: the formats
        # are compared with apply of that baseline written as a version-1 file.
        applied = path("cal.json")
        if calibration["format_version"] == 2:
            applied = path("baseline.json")
            with open(applied, "w") as out:
                json.dump(without_terms(calibration), out)
        run(binary("apply"), "--calibration=" + applied, "--in=" + path("xsens.csv"),
            "--out=" + path("corrected.csv"))
        acc_raw, gyr_raw = read_log(path("xsens.csv"))
        acc_apply, gyr_apply = read_corrected(path("corrected.csv"))
        if len(acc_apply) != len(acc_raw) or len(acc_raw) < 50000:
            fail("apply did not correct the whole session")

        # imu_tk
        run(binary("export_calibration"), "--calibration=" + path("cal.json"), "--format=imu_tk",
            "--out=" + path("xsens"))
        acc_text = open(path("xsens_acc.calib")).read()
        gyr_text = open(path("xsens_gyro.calib")).read()
        d_acc = worst(imu_tk_apply(acc_text, acc_raw), acc_apply)
        d_gyr = worst(imu_tk_apply(gyr_text, gyr_raw), gyr_apply)
        print(f"imu_tk: accelerometer {d_acc:.3g}, gyroscope {d_gyr:.3g} (relative)")
        if not (d_acc <= TOLERANCE and d_gyr <= TOLERANCE):
            fail(f"imu_tk's .calib pair applied differs from apply's by {d_acc:.3g}, {d_gyr:.3g}")
        # A broken export: misalignment yz's sign flipped in the accelerometer's T.
        misalignment, scale, bias = imu_tk_load(acc_text)
        misalignment[0, 1] = -misalignment[0, 1]
        broken = "\n".join(" ".join(repr(v) for v in row) for row in
                           [*misalignment, *scale, *[[b] for b in bias]])
        if worst(imu_tk_apply(broken, acc_raw), acc_apply) <= TOLERANCE:
            fail("the imu_tk check did not see a flipped misalignment")

        # imucal
        run(binary("export_calibration"), "--calibration=" + path("cal.json"), "--format=imucal",
            "--out=" + path("imucal.json"))
        imucal_text = open(path("imucal.json")).read()
        acc_out, gyr_out, info = imucal_apply(imucal_text, acc_raw, gyr_raw, "a.u.", "a.u.")
        if info["acc_unit"] != "m/s^2" or info["gyr_unit"] != "deg/s":
            fail(f"imucal's units are {info['acc_unit']}, {info['gyr_unit']}")
        d_acc = worst(acc_out, acc_apply)
        d_gyr = worst(gyr_out * math.pi / 180, gyr_apply)
        print(f"imucal: accelerometer {d_acc:.3g}, gyroscope {d_gyr:.3g} (relative)")
        if not (d_acc <= TOLERANCE and d_gyr <= TOLERANCE):
            fail(f"imucal's calibration applied differs from apply's by {d_acc:.3g}, {d_gyr:.3g}")
        broken = json.loads(imucal_text)
        broken["R_a"] = np.array(broken["R_a"]).T.tolist()
        if worst(imucal_apply(json.dumps(broken), acc_raw, gyr_raw, "a.u.", "a.u.")[0],
                 acc_apply) <= TOLERANCE:
            fail("the imucal check did not see R_a transposed")

        # Kalibr
        run(binary("export_calibration"), "--calibration=" + path("cal.json"), "--format=kalibr",
            "--allan=" + path("acc_allan.json"), "--gyro_allan=" + path("gyro_allan.json"),
            "--out=" + path("imu.yaml"))
        kalibr_text = open(path("imu.yaml")).read()
        expected = kalibr_expected(calibration, json.load(open(path("acc_allan.json"))),
                                   json.load(open(path("gyro_allan.json"))))
        difference = kalibr_check(kalibr_text, expected)
        print(f"kalibr: {difference:.3g} (relative); " +
              ", ".join(f"{k} {v:.6g}" for k, v in expected.items()))
        if not difference <= TOLERANCE:
            fail(f"Kalibr's imu.yaml differs from the Allan fits carried through by {difference:.3g}")
        broken = yaml.safe_load(kalibr_text)
        broken["gyroscope_random_walk"] /= 2
        if kalibr_check(yaml.safe_dump(broken), expected) <= TOLERANCE:
            fail("the Kalibr check did not see a halved random walk")
    print("PASS")


if __name__ == "__main__":
    main()
