"""The Python module against the binaries (docs/python.md): on imu_tk's Xsens log,
accelcal.calibrate gives calibrate_imu --mode=ml's parameters, covariance and verdict, and
accelcal.apply gives apply's corrected CSV, to 1e-12 relative; bad input raises accelcal.Error
(a ValueError) with the binary's one-line message.

Run by ctest (Python.ModuleMatchesTheBinaries) with PYTHONPATH at build/python and
ACCELCAL_BIN_DIR at build/bin.
"""
import csv
import json
import os
import subprocess

import numpy as np
import pytest

import accelcal

BIN_DIR = os.environ.get("ACCELCAL_BIN_DIR", "")
# As the C++ tests: ACCELCAL_IMU_TK_DATA when set, else ../shared/data/imu_tk-xsens (ctest says
# where, ACCELCAL_DEFAULT_IMU_TK_DATA).
DATA = os.environ.get("ACCELCAL_IMU_TK_DATA") or os.environ.get("ACCELCAL_DEFAULT_IMU_TK_DATA", "")
ACC = os.path.join(DATA, "xsens_acc.mat")
GYRO = os.path.join(DATA, "xsens_gyro.mat")
G = 9.81744
GYRO_GAIN = 0.000159795

needs_data = pytest.mark.skipif(not os.path.exists(ACC), reason="no imu_tk Xsens data at " + ACC)


def run_binary(name, *args):
    return subprocess.run([os.path.join(BIN_DIR, name), *args], capture_output=True, text=True)


def assert_close(actual, expected, rtol=1e-12, what=""):
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    scale = np.maximum(np.abs(expected), np.finfo(float).tiny)
    worst = np.max(np.abs(actual - expected) / scale) if expected.size else 0.0
    assert worst <= rtol, f"{what}: largest relative difference {worst:.3g} > {rtol:g}"


@pytest.fixture(scope="module")
def binary_ml(tmp_path_factory):
    out = tmp_path_factory.mktemp("ml")
    json_path, cal_path = out / "ml.json", out / "cal.json"
    result = run_binary("calibrate_imu", f"--log={ACC}", f"--g={G}", "--mode=ml",
                        f"--json={json_path}", f"--calibration_out={cal_path}")
    assert result.returncode == 0, result.stderr
    return json.loads(json_path.read_text()), cal_path, result.stdout


@pytest.fixture(scope="module")
def module_ml():
    return accelcal.calibrate(ACC, g=G)


def test_the_module_has_its_api():
    for name in ("read_log", "calibrate", "apply", "apply_gyroscope", "Error", "Log",
                 "Calibration"):
        assert hasattr(accelcal, name), name
    assert issubclass(accelcal.Error, ValueError)
    version = run_binary("calibrate_imu", "--version").stdout
    assert accelcal.__version__ and accelcal.__version__ in version
    # The same line as every binary's --version: version, commit and build type.
    assert version.strip() == "calibrate_imu version " + accelcal.build_info
    assert accelcal.__git_commit__ in accelcal.build_info
    assert accelcal.__build_type__ in accelcal.build_info


@needs_data
def test_read_log_gives_numpy_arrays_and_the_files_checksum():
    log = accelcal.read_log(ACC)
    assert log.acc.shape == (len(log), 3) and log.time_s.shape == (len(log),)
    assert log.gyro is None
    assert np.all(np.diff(log.time_s) > 0)
    assert len(log.sha256) == 64 and log.source["log"]["sha256"] == log.sha256
    paired = accelcal.read_log(ACC, gyro_log=GYRO)
    assert paired.gyro.shape == paired.acc.shape


@needs_data
def test_calibrate_gives_the_binarys_parameters_covariance_and_verdict(binary_ml, module_ml):
    expected, _, stdout = binary_ml
    cal = module_ml
    assert set(cal.names) == set(expected["parameters"].keys())
    assert_close([cal.parameters[n] for n in cal.names],
                 [expected["parameters"][n] for n in cal.names], what="parameters")
    assert_close(cal.stddev, [expected["stddev"][n] for n in cal.names], what="stddev")
    assert cal.verdict_kind == expected["verdict"]
    assert cal.verdict == expected["verdict_text"]
    # The very line the binary prints.
    assert f"Verdict ({cal.verdict_kind}): {cal.verdict}" in stdout
    # The whole JSON, provenance aside: every number to 1e-12.
    provenance = ("command_line", "accelcal_version", "source", "input_files")
    mine = {k: v for k, v in json.loads(cal.json()).items() if k not in provenance}
    compare_json(mine, {k: v for k, v in expected.items() if k not in provenance}, "json")


def compare_json(actual, expected, where):
    if isinstance(expected, dict):
        assert isinstance(actual, dict) and set(actual) == set(expected), where
        for key in expected:
            compare_json(actual[key], expected[key], where + "." + key)
    elif isinstance(expected, list):
        assert isinstance(actual, list) and len(actual) == len(expected), where
        for i, (a, e) in enumerate(zip(actual, expected)):
            compare_json(a, e, f"{where}[{i}]")
    elif isinstance(expected, float) and not isinstance(expected, bool):
        assert_close(actual, expected, what=where)
    else:
        assert actual == expected, where


@needs_data
def test_the_covariance_is_the_calibration_files(binary_ml, module_ml, tmp_path):
    _, cal_path, _ = binary_ml
    written = json.loads(cal_path.read_text())
    assert_close(module_ml.covariance, written["covariance"], what="covariance")
    module_ml.write(tmp_path / "mine.json")
    mine = json.loads((tmp_path / "mine.json").read_text())
    # The whole file, but for when and by what it was written.
    varying = ("created_utc", "command_line", "accelcal_version")
    compare_json({k: v for k, v in mine.items() if k not in varying},
                 {k: v for k, v in written.items() if k not in varying}, "calibration file")


@needs_data
def test_apply_gives_the_binarys_csv(binary_ml, tmp_path):
    _, cal_path, _ = binary_ml
    out = tmp_path / "corrected.csv"
    result = run_binary("apply", f"--calibration={cal_path}", f"--in={ACC}", f"--out={out}")
    assert result.returncode == 0, result.stderr
    rows = [r for r in csv.reader(line for line in out.open() if not line.startswith("#"))]
    header, rows = rows[0], np.array(rows[1:], dtype=float)
    log = accelcal.read_log(ACC, even=False)
    corrected, sigma = accelcal.apply(str(cal_path), log.acc)
    columns = {name: i for i, name in enumerate(header)}
    expected = rows[:, [columns["ax_mps2"], columns["ay_mps2"], columns["az_mps2"]]]
    assert_close(corrected, expected, what="corrected")
    expected_sigma = rows[:, [columns[f"sigma_a{k}_mps2"] for k in "xyz"]]
    assert_close(sigma, expected_sigma, rtol=1e-8, what="sigma (9 digits in the CSV)")
    # A Calibration object corrects as its file does.
    same, _ = accelcal.apply(accelcal.calibrate(log, g=G), log.acc[:100])
    assert_close(same, corrected[:100], what="object against file")


@needs_data
def test_a_log_from_arrays_calibrates_as_its_file(module_ml):
    read = accelcal.read_log(ACC)
    log = accelcal.Log(read.time_s, read.acc, name="xsens arrays")
    assert np.array_equal(log.acc, read.acc) and np.array_equal(log.time_s, read.time_s)
    cal = accelcal.calibrate(log, g=G)
    assert_close(cal.values, module_ml.values, what="parameters from arrays")
    assert cal.verdict == module_ml.verdict and len(log.sha256) == 64
    with pytest.raises(accelcal.Error, match="^bad arrays: "):
        accelcal.Log(read.time_s[::-1], read.acc, name="bad arrays")
    with pytest.raises(ValueError):
        accelcal.Log(read.time_s[:10], read.acc)


@needs_data
def test_the_gyroscope_matches_the_binary(tmp_path):
    json_path = tmp_path / "gyro.json"
    result = run_binary("calibrate_imu", f"--log={ACC}", f"--gyro_log={GYRO}", f"--g={G}",
                        "--mode=ml", f"--initial_gyro_gain={GYRO_GAIN}", f"--json={json_path}")
    assert result.returncode == 0, result.stderr
    expected = json.loads(json_path.read_text())["gyroscope"]
    cal = accelcal.calibrate(ACC, gyro_log=GYRO, g=G, initial_gyro_gain=GYRO_GAIN)
    assert cal.gyroscope is not None
    assert cal.gyroscope.verdict_kind == expected["verdict"]
    mine = json.loads(cal.json())["gyroscope"]
    compare_json(mine, expected, "gyroscope")
    # The calibration is the model discovery settled on: on this pair its gyroscope carries a
    # g-sensitivity (issue 44, item 7), which reads the same samples' accelerometer rows.
    assert cal.gyroscope.names == expected["parameter_order"]
    assert len(expected["effect_terms"]) == 9
    log = accelcal.read_log(ACC, gyro_log=GYRO)
    with pytest.raises(accelcal.Error, match="give acc="):
        accelcal.apply_gyroscope(cal, log.gyro[:10])
    rate, sigma = accelcal.apply_gyroscope(cal, log.gyro[:10], acc=log.acc[:10])
    assert rate.shape == (10, 3) and np.all(sigma > 0)


def cal_log_gyro(acc, gyro):
    return accelcal.read_log(acc, gyro_log=gyro).gyro


def binary_error(*args):
    result = run_binary("calibrate_imu", *args)
    assert result.returncode == 2
    prefix = "calibrate_imu: error: "
    assert result.stderr.startswith(prefix), result.stderr
    return result.stderr[len(prefix):].strip()


def test_a_missing_log_raises_the_binarys_message(tmp_path):
    missing = str(tmp_path / "no_such_log.csv")
    with pytest.raises(accelcal.Error) as error:
        accelcal.read_log(missing)
    assert str(error.value) == binary_error(f"--log={missing}", "--mode=ml")


@needs_data
def test_a_wrong_unit_raises_the_binarys_message():
    with pytest.raises(ValueError) as error:
        accelcal.calibrate(ACC, g=G, unit="m/s^2")
    assert str(error.value) == binary_error(f"--log={ACC}", f"--g={G}", "--mode=ml",
                                            "--unit=m/s^2")


@needs_data
@pytest.mark.parametrize("keyword,value,flag", [
    ("g", 1.0, "--g=1"), ("window", 5, "--window=5"), ("window", 12, "--window=12"),
    ("alpha", 0.7, "--alpha=0.7"), ("initial_offset", "abc", "--initial_offset=abc"),
    ("noise", "pink", "--noise=pink"), ("unit", "furlong", "--unit=furlong"),
    ("detector", "eyes", "--detector=eyes")])
def test_a_bad_keyword_raises_the_binarys_message(keyword, value, flag):
    with pytest.raises(accelcal.Error) as error:
        accelcal.calibrate(ACC, **{keyword: value})
    expected = binary_error(f"--log={ACC}", "--mode=ml", flag)
    assert str(error.value) == expected.replace("; see calibrate_imu --help", "")


def test_bad_arguments_raise_value_errors_not_aborts(tmp_path):
    with pytest.raises(ValueError):
        accelcal.apply(str(tmp_path / "no_such_calibration.json"), np.zeros((3, 3)))
    text = tmp_path / "log.csv"
    text.write_text("t,ax,ay,az\n0,1,2\n")
    with pytest.raises(ValueError):
        accelcal.read_log(text)
    if os.path.exists(ACC):
        with pytest.raises(ValueError):
            accelcal.calibrate(ACC, g=1.0)
        cal = accelcal.calibrate(ACC, g=G)
        with pytest.raises(ValueError):
            accelcal.apply(cal, np.zeros((4, 2)))
        with pytest.raises(ValueError):
            accelcal.apply(cal, np.array([[1e300, 0.0, 0.0]]))
        with pytest.raises(ValueError):
            accelcal.apply_gyroscope(cal, np.zeros((2, 3)))


def test_an_array_where_a_log_is_expected_is_an_accelcal_error():
    """calibrate(array) raised os.fspath's TypeError; it is accelcal.Error naming what to give."""
    with pytest.raises(accelcal.Error, match=r"not a ndarray; arrays: accelcal.Log\(time_s, acc"):
        accelcal.calibrate(np.zeros((100, 3)))
    with pytest.raises(accelcal.Error, match="expected a log's path"):
        accelcal.read_log(3.5)
