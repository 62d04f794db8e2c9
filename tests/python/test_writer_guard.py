"""The Python module's writers go through the binaries' output-path guard (io/output_paths.h;
issue 45, "Data lost"): Calibration.write never replaces an input of the calibration (by path,
through a link or a relative spelling, or by identity: a hard link), a folder or a special file;
it raises accelcal.Error with one line naming the path, and writes nothing, not even a
temporary file.

Run by ctest (Python.WriteNeverReplacesAnInputOrASpecialFile) with PYTHONPATH at build/python.
"""
import hashlib
import os

import pytest

import accelcal
import hand_held

DATA = os.environ.get("ACCELCAL_IMU_TK_DATA") or os.environ.get("ACCELCAL_DEFAULT_IMU_TK_DATA", "")
ACC = os.path.join(DATA, "xsens_acc.mat")
GYRO = os.path.join(DATA, "xsens_gyro.mat")


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    folder = tmp_path_factory.mktemp("session")
    (path, _), = hand_held.write_devices(str(folder), 1, seed=5)
    os.remove(folder / "truth.csv")
    return path, accelcal.calibrate(path)


def expect_refused(action, path, fragment):
    with pytest.raises(accelcal.Error) as error:
        action()
    message = str(error.value)
    assert "\n" not in message, message
    assert str(path) in message, message
    assert fragment in message, message


def test_write_onto_the_log_is_refused_and_the_log_kept(session):
    log, cal = session
    size, digest = os.path.getsize(log), sha256(log)
    folder = os.path.dirname(log)
    before = sorted(os.listdir(folder))
    expect_refused(lambda: cal.write(log), log, "is the input")
    # Spelt another way, or a link to it: the same file.
    relative = os.path.relpath(log)
    expect_refused(lambda: cal.write(relative), relative, "is the input")
    dotted = os.path.join(folder, ".", os.path.basename(log))
    expect_refused(lambda: cal.write(dotted), dotted, "is the input")
    hard = os.path.join(folder, "hard_link.csv")
    os.link(log, hard)
    expect_refused(lambda: cal.write(hard), hard, "is the input")
    os.remove(hard)
    assert os.path.getsize(log) == size and sha256(log) == digest
    assert sorted(os.listdir(folder)) == before


def test_write_through_a_link_or_onto_a_folder_or_a_fifo_is_refused(session, tmp_path):
    log, cal = session
    link = tmp_path / "link.json"
    os.symlink(log, link)
    expect_refused(lambda: cal.write(link), link, "symbolic link")
    expect_refused(lambda: cal.write(tmp_path), tmp_path, "folder")
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    expect_refused(lambda: cal.write(fifo), fifo, "FIFO")
    expect_refused(lambda: cal.write(tmp_path / "no" / "cal.json"), tmp_path / "no" / "cal.json",
                   "does not exist")
    assert sorted(os.listdir(tmp_path)) == ["fifo", "link.json"]
    assert os.readlink(link) == log


def test_write_to_a_new_file_or_over_an_earlier_calibration_works(session, tmp_path):
    log, cal = session
    path = tmp_path / "cal.json"
    cal.write(path)
    assert path.read_text() == cal.file_text()
    path.write_text("an earlier calibration\n")
    cal.write(str(path))
    assert path.read_text() == cal.file_text()
    assert sorted(os.listdir(tmp_path)) == ["cal.json"]


@pytest.mark.skipif(not os.path.exists(ACC), reason="no imu_tk Xsens data at " + ACC)
def test_write_onto_the_gyroscope_log_is_refused(tmp_path):
    # A copy: the shared data must never be at risk, even from a broken build.
    acc, gyro = tmp_path / "acc.mat", tmp_path / "gyro.mat"
    acc.write_bytes(open(ACC, "rb").read())
    gyro.write_bytes(open(GYRO, "rb").read())
    digest = sha256(gyro)
    cal = accelcal.calibrate(str(acc), g=9.81744, gyro_log=str(gyro),
                             initial_gyro_gain=0.000159795)
    expect_refused(lambda: cal.write(gyro), gyro, "is the input")
    expect_refused(lambda: cal.write(acc), acc, "is the input")
    assert sha256(gyro) == digest
    assert sorted(os.listdir(tmp_path)) == ["acc.mat", "gyro.mat"]


def test_a_log_from_arrays_names_no_file(tmp_path):
    # A Log built from arrays has no input file: any new path is fine, even one that happens to
    # be spelt like its name.
    (log, _), = hand_held.write_devices(str(tmp_path / "arrays"), 1, seed=6)
    read = accelcal.read_log(log)
    cal = accelcal.calibrate(accelcal.Log(read.time_s, read.acc, name="cal.json"))
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        cal.write("cal.json")
    finally:
        os.chdir(here)
    assert (tmp_path / "cal.json").read_text() == cal.file_text()
