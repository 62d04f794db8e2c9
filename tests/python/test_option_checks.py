"""The Python module refuses what the binaries refuse, with their message (issue 45, "Silent
wrong answers"): accelcal.calibrate's numeric keywords are checked by the same validation as
calibrate_imu's flags (reporting/calibrate_imu_options.h), and accelcal.apply refuses values in
another unit than the calibration's by apply's own check of the median |a|
(reporting/apply_checks.h).

Run by ctest (Python.OptionsAndUnitsAreCheckedAsTheBinariesCheckThem) with PYTHONPATH at
build/python and ACCELCAL_BIN_DIR at build/bin.
"""
import math
import os
import subprocess

import numpy as np
import pytest

import accelcal
import hand_held

BIN_DIR = os.environ.get("ACCELCAL_BIN_DIR", "")


def run_binary(name, *args):
    return subprocess.run([os.path.join(BIN_DIR, name), *args], capture_output=True, text=True)


def binary_error(name, *args):
    """The binary's one-line refusal, without its 'NAME: error: ' and '; see NAME --help'."""
    result = run_binary(name, *args)
    assert result.returncode == 2, (result.returncode, result.stderr)
    prefix = name + ": error: "
    assert result.stderr.startswith(prefix) and result.stderr.count("\n") == 1, result.stderr
    return result.stderr[len(prefix):].strip().replace(f"; see {name} --help", "")


@pytest.fixture(scope="module")
def device(tmp_path_factory):
    folder = tmp_path_factory.mktemp("device")
    (path, _), = hand_held.write_devices(str(folder), 1, seed=11)
    return path


def flag_text(value):
    """The value as a user would type the flag: an int as it is, a float in the shortest of
    %.15g, %.16g, %.17g that reads back the same (the digits the module's message shows)."""
    if isinstance(value, int):
        return str(value)
    if math.isnan(value):
        return "nan"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    for digits in (15, 16, 17):
        text = f"{value:.{digits}g}"
        if float(text) == value:
            return text
    return repr(value)


@pytest.mark.parametrize("keyword,value", [
    ("threshold_factor", float("nan")), ("threshold_factor", -3.0), ("threshold_factor", 0.5),
    ("interval_samples", 0), ("interval_samples", -5), ("interval_samples", 1),
    ("min_intervals", -1), ("min_intervals", 2),
    ("init_rest_s", -5.0), ("init_rest_s", float("nan")), ("init_rest_s", 0.0),
    ("min_interval_s", float("inf")), ("min_interval_s", -1.0), ("min_interval_s", float("nan")),
    ("g", float("nan")), ("g", 98.1), ("initial_gyro_gain", -1.0),
    ("window", 100003), ("window", 9)])
def test_a_keyword_out_of_its_range_raises_the_binarys_message(device, keyword, value):
    with pytest.raises(accelcal.Error) as error:
        accelcal.calibrate(device, **{keyword: value})
    expected = binary_error("calibrate_imu", f"--log={device}", "--mode=ml",
                            f"--{keyword}={flag_text(value)}")
    assert str(error.value) == expected


def test_the_range_limits_themselves_are_accepted(device):
    # The closed ends are in range: the run goes on (and calibrates, on this session).
    cal = accelcal.calibrate(device, threshold_factor=10.0, interval_samples=2, min_intervals=3,
                             min_interval_s=0.0)
    assert cal.poses >= 12


def test_apply_of_a_count_calibration_to_values_in_mps2_is_refused(device, tmp_path):
    cal = accelcal.calibrate(device)
    assert cal.unit == "count"
    log = accelcal.read_log(device)
    corrected, _ = accelcal.apply(cal, log.acc)
    assert abs(np.median(np.linalg.norm(corrected, axis=1)) - 9.81) < 0.1
    # The corrected values, in m/s^2, given again as if they were the outputs in counts.
    cal_path = str(tmp_path / "cal.json")
    cal.write(cal_path)
    with pytest.raises(accelcal.Error) as error:
        accelcal.apply(cal_path, corrected)
    message = str(error.value)
    assert "not about g = 9.81" in message and "(count)" in message, message
    # apply on a log of the same values: the same check, the same words after the log's name.
    mps2_log = tmp_path / "in_mps2.csv"
    with open(mps2_log, "w") as f:
        f.write("t,ax,ay,az\n")
        for t, row in zip(log.time_s, corrected):
            f.write(f"{t!r},{row[0]!r},{row[1]!r},{row[2]!r}\n")
    expected = binary_error("apply", f"--calibration={cal_path}", f"--in={mps2_log}",
                            f"--out={tmp_path / 'out.csv'}")
    assert message.split(": ", 1)[1] == expected.split(": ", 1)[1], (message, expected)
    assert not os.path.exists(tmp_path / "out.csv")
    # A Calibration object, not its file: the same refusal.
    with pytest.raises(accelcal.Error, match="not about g"):
        accelcal.apply(cal, corrected)
