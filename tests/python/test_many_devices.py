"""tools/many_devices.py on a local Dask cluster (2 worker processes) with simulated devices
(hand_held.py): one calibration file per device that calibrates, one summary table, a broken
log recorded as a failed row without stopping the others, and every device's gains and
offsets within 5 sigma of its truth.

Run by ctest (Python.ManyDevicesOnALocalDaskCluster) with PYTHONPATH at build/python and
ACCELCAL_SOURCE_DIR at the repository.
"""
import csv
import json
import os
import subprocess
import sys

import hand_held

SOURCE_DIR = os.environ.get("ACCELCAL_SOURCE_DIR",
                            os.path.join(os.path.dirname(__file__), "..", ".."))
SCRIPT = os.path.join(SOURCE_DIR, "tools", "many_devices.py")


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True,
                          timeout=600)


def test_a_folder_of_devices_calibrates_on_a_local_cluster(tmp_path):
    logs = tmp_path / "logs"
    devices = hand_held.write_devices(str(logs), 4, seed=7)
    os.remove(logs / "truth.csv")
    # A device whose log was cut short: its row says why, the others calibrate.
    (logs / "device_broken.csv").write_text("t,ax,ay,az\n0.00,1,2,3\n0.01,1,2")
    out = tmp_path / "out"
    result = run(f"--logs={logs}", f"--out={out}", "--workers=2", "--g=9.81")
    # Exit 1: the run completed, one device failed (issue 48); the outputs are written.
    assert result.returncode == 1, result.stderr
    assert "1 of 5 devices failed" in result.stderr
    names = sorted(os.listdir(out))
    # The calibrations, the summary and the marker every output folder of accelcal's carries
    # (what lets a later --overwrite replace it).
    assert names == sorted([f"device_{d:02d}.calibration.json" for d in range(4)] +
                           ["summary.csv", ".accelcal-output"]), names
    rows = {r["device"]: r for r in csv.DictReader(open(out / "summary.csv"))}
    assert len(rows) == 5
    broken = rows["device_broken"]
    assert broken["status"] == "failed" and "device_broken.csv" in broken["message"]
    assert "device_broken" in result.stdout and "4 of 5 devices calibrated in" in result.stdout
    for path, truth in devices:
        row = rows[os.path.basename(path)[:-4]]
        assert row["status"] == "ok", row["message"]
        assert len(row["sha256"]) == 64 and int(row["poses"]) >= 20
        for name in ("gain_x", "gain_y", "gain_z", "offset_x", "offset_y", "offset_z"):
            z = (float(row[name]) - truth[name]) / float(row[name + "_sigma"])
            assert abs(z) < 5, f"{row['device']} {name}: {z:.2f} sigma from the truth"
        written = json.loads((out / row["calibration_file"]).read_text())
        assert written["model"]["geometry"] == "triad"
        assert written["fit"]["verdict_code"] == row["verdict"]


def test_an_existing_output_is_kept_without_overwrite(tmp_path):
    logs = tmp_path / "logs"
    hand_held.write_devices(str(logs), 1, seed=3)
    os.remove(logs / "truth.csv")
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep").write_text("mine")
    result = run(f"--logs={logs}", f"--out={out}", "--workers=1")
    assert result.returncode != 0 and "--overwrite" in result.stderr
    assert os.listdir(out) == ["keep"]


def test_no_matching_log_is_bad_input(tmp_path):
    result = run(f"--logs={tmp_path}/*.csv", f"--out={tmp_path}/out", "--workers=1")
    assert result.returncode == 2 and "no log matches" in result.stderr
    assert not os.path.exists(tmp_path / "out")


def test_a_bad_option_is_one_refusal_before_any_work(tmp_path):
    """--g out of calibrate_imu's range: one line and exit 2 before Dask starts, nothing written
    (it was one failed row per device and exit 0)."""
    logs = tmp_path / "logs"
    hand_held.write_devices(str(logs), 2, seed=5)
    out = tmp_path / "out"
    result = run(f"--logs={logs}", f"--out={out}", "--workers=1", "--g=98.1")
    assert result.returncode == 2, (result.returncode, result.stdout, result.stderr)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("many_devices: error: ") and "--g" in lines[0]
    assert not out.exists()
