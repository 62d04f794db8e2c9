"""tools/many_devices.py never deletes or alters a user's files (issue 45, "Data lost"): --out is
checked before any work by the binaries' own output-path guard (io/output_paths.h, through the
module's accelcal.check_output), so that an --out that is an input, holds one, lies inside the
logs folder, is a file, a link or a special file, or is a folder accelcal did not write (no
.accelcal-output marker) is refused in one line, exit status 2, with nothing written; and the
folder that --overwrite may replace is replaced whole or not at all (io/atomic_file.h's
WriteDirectoryAtomically, through accelcal.write_folder).

Run by ctest (Python.ManyDevicesNeverDeletesOrAltersAUsersFiles) with PYTHONPATH at build/python
and ACCELCAL_SOURCE_DIR at the repository.
"""
import hashlib
import importlib.util
import os
import subprocess
import sys

import pytest

import hand_held

SOURCE_DIR = os.environ.get("ACCELCAL_SOURCE_DIR",
                            os.path.join(os.path.dirname(__file__), "..", ".."))
SCRIPT = os.path.join(SOURCE_DIR, "tools", "many_devices.py")
MARKER = ".accelcal-output"


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True,
                          timeout=600)


def tree(path):
    """Every entry under `path` (path included): its kind and, for a file, its bytes' SHA-256;
    a change to any of them, a removal or an addition shows."""
    entries = {}
    if os.path.islink(path) or not os.path.isdir(path):
        return {".": describe(path)}
    for root, dirs, files in os.walk(path):
        for name in dirs + files:
            full = os.path.join(root, name)
            entries[os.path.relpath(full, path)] = describe(full)
    entries["."] = "folder"
    return entries


def describe(path):
    if os.path.islink(path):
        return "link to " + os.readlink(path)
    if os.path.isdir(path):
        return "folder"
    if not os.path.isfile(path):
        return "special"
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


@pytest.fixture
def logs(tmp_path_factory):
    """A folder of one simulated device's log, inside a parent holding a file of the user's;
    a new one for each test, so that a failing test cannot hide another's result."""
    parent = tmp_path_factory.mktemp("user")
    folder = parent / "logs"
    hand_held.write_devices(str(folder), 1, seed=3)
    os.remove(folder / "truth.csv")
    (parent / "notes.txt").write_text("the user's own file\n")
    return folder


def expect_refused(result, path, fragment):
    """The one-line refusal: exit 2, 'many_devices: error: ' naming the path, nothing on stdout."""
    assert result.returncode == 2, (result.returncode, result.stdout, result.stderr)
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("many_devices: error: "), result.stderr
    assert str(path) in lines[0], result.stderr
    assert fragment in lines[0], result.stderr
    assert result.stdout == "", result.stdout


def no_temporaries(folder):
    """Nothing beside the outputs: no staging folder, no hidden .NAME.XXXX.old."""
    leftovers = [n for n in os.listdir(folder) if ".tmp." in n or n.endswith(".old")]
    assert leftovers == [], leftovers


def test_out_the_logs_folder_with_overwrite_is_refused_and_the_logs_kept(logs):
    before = tree(logs.parent)
    result = run(f"--logs={logs}", f"--out={logs}", "--overwrite", "--workers=1")
    expect_refused(result, logs, "never contains the data it reads")
    assert tree(logs.parent) == before


def test_out_the_logs_folders_parent_is_refused_and_the_parent_kept(logs):
    before = tree(logs.parent)
    result = run(f"--logs={logs}", f"--out={logs.parent}", "--overwrite", "--workers=1")
    expect_refused(result, logs.parent, "never contains the data it reads")
    assert tree(logs.parent) == before
    # The same through a glob of the logs: the folder holds an input file.
    result = run(f"--logs={logs}/*.csv", f"--out={logs.parent}", "--overwrite", "--workers=1")
    expect_refused(result, logs.parent, "never contains the data it reads")
    assert tree(logs.parent) == before


def test_out_inside_the_logs_folder_or_a_link_to_it_is_refused(logs, tmp_path):
    before = tree(logs.parent)
    result = run(f"--logs={logs}", f"--out={logs}/calibrations", "--workers=1")
    expect_refused(result, f"{logs}/calibrations", "lies inside the data folder")
    link = tmp_path / "link"
    os.symlink(logs, link)
    result = run(f"--logs={logs}", f"--out={link}", "--overwrite", "--workers=1")
    expect_refused(result, link, "symbolic link")
    assert os.readlink(link) == str(logs)
    # The logs named through the link: still the same folder (realpath).
    result = run(f"--logs={link}", f"--out={logs}", "--overwrite", "--workers=1")
    expect_refused(result, logs, "never contains the data it reads")
    assert tree(logs.parent) == before


def test_a_folder_accelcal_did_not_write_is_never_emptied(logs, tmp_path):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "thesis.tex").write_text("years of work\n")
    before = tree(mine)
    result = run(f"--logs={logs}", f"--out={mine}", "--overwrite", "--workers=1")
    expect_refused(result, mine, MARKER)
    assert tree(mine) == before
    no_temporaries(tmp_path)


def test_an_existing_file_or_special_file_is_refused_untouched(logs, tmp_path):
    target = tmp_path / "results"
    target.write_text("a file of the user's\n")
    for flags in ([], ["--overwrite"]):
        result = run(f"--logs={logs}", f"--out={target}", "--workers=1", *flags)
        expect_refused(result, target, "is a file")
        assert target.read_text() == "a file of the user's\n"
        assert sorted(os.listdir(tmp_path)) == ["results"]
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    result = run(f"--logs={logs}", f"--out={fifo}", "--overwrite", "--workers=1")
    expect_refused(result, fifo, "FIFO")
    assert not os.path.islink(fifo) and not os.path.isfile(fifo) and os.path.exists(fifo)
    assert sorted(os.listdir(tmp_path)) == ["fifo", "results"]


def test_out_in_a_folder_that_does_not_exist_is_refused_not_created(logs, tmp_path):
    result = run(f"--logs={logs}", f"--out={tmp_path}/no/such/out", "--workers=1")
    expect_refused(result, f"{tmp_path}/no/such/out", "does not exist")
    assert os.listdir(tmp_path) == []


def test_overwrite_replaces_the_folder_it_wrote_and_only_that(logs, tmp_path):
    out = tmp_path / "out"
    first = run(f"--logs={logs}", f"--out={out}", "--workers=1")
    assert first.returncode == 0, first.stderr
    assert sorted(os.listdir(out)) == sorted([MARKER, "device_00.calibration.json",
                                              "summary.csv"])
    # Without --overwrite: refused, kept.
    before = tree(out)
    again = run(f"--logs={logs}", f"--out={out}", "--workers=1")
    expect_refused(again, out, "--overwrite")
    assert tree(out) == before
    # With it: replaced whole (a file the earlier run did not write is gone with it).
    (out / "stale.txt").write_text("from before\n")
    second = run(f"--logs={logs}", f"--out={out}", "--overwrite", "--workers=1")
    assert second.returncode == 0, second.stderr
    assert sorted(os.listdir(out)) == sorted([MARKER, "device_00.calibration.json",
                                              "summary.csv"])
    no_temporaries(tmp_path)


def load_script():
    spec = importlib.util.spec_from_file_location("many_devices", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_failed_write_leaves_the_old_output_and_no_temporary(tmp_path):
    many_devices = load_script()
    out = tmp_path / "out"
    out.mkdir()
    (out / MARKER).write_text("This folder was written by accelcal\n")
    (out / "summary.csv").write_text("the earlier run's\n")
    before = tree(out)
    # The second file cannot be written inside the new folder (its name leaves it): the write
    # fails after the first file, and nothing of it may show.
    import accelcal

    with pytest.raises(accelcal.Error, match="escaped.csv"):
        many_devices.write_outputs(str(out), {"a.calibration.json": "{}\n",
                                              "../escaped.csv": "x\n"}, overwrite=True)
    assert tree(out) == before
    assert sorted(os.listdir(tmp_path)) == ["out"]
