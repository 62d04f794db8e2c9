"""Runs every binary that writes JSON and checks its output against docs/json.md.

    python3 -I -S json_schema_test.py BIN_DIR SOURCE_DIR COURSE_DATA CATALOGUE_UNITS

For each output: every key of its table is present with a documented type (null only where
the table says `or null`, and never 0 there), no top-level key is missing from the table, the
provenance keys are there, and every `units` map (and one beside every `parameters` map) agrees
with the catalogue (CATALOGUE_UNITS prints it). Python's standard library alone.
"""

import json
import os
import re
import subprocess
import sys
import tempfile

SCALARS = {"string", "number", "integer", "boolean", "object", "array", "null"}


def parse_schemas(markdown_path):
    """{name: [(key, [type, ...]), ...]} from the ## `name` sections' tables."""
    schemas = {}
    current = None
    with open(markdown_path, encoding="utf-8") as handle:
        for line in handle:
            heading = re.match(r"^## `(\w+)`", line)
            if heading:
                current = heading.group(1)
                schemas[current] = []
                continue
            if line.startswith("## "):
                current = None
                continue
            row = re.match(r"^\| `([^`]+)` \| ([^|]+) \|", line)
            if current is None or not row:
                continue
            types = [t.strip() for t in row.group(2).split(" or ")]
            for t in types:
                if t not in SCALARS and not re.fullmatch(r"object: \w+", t):
                    raise SystemExit(f"docs/json.md: `{current}`: key {row.group(1)}: unknown type '{t}'")
            schemas[current].append((row.group(1), types))
    return schemas


def type_ok(value, type_name):
    if type_name == "null":
        return value is None
    if type_name == "string":
        return isinstance(value, str)
    if type_name == "boolean":
        return isinstance(value, bool)
    if type_name == "integer":
        return isinstance(value, int) and not isinstance(value, bool)
    if type_name == "number":
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    if type_name == "array":
        return isinstance(value, list)
    return isinstance(value, dict)  # object, object: NAME


def values_at(document, path):
    """The values at a dotted path (`a.b`, `a[].b`), skipping a null parent; (where, value)."""
    found = [("", document)]
    for part in path.split("."):
        each = part.endswith("[]")
        key = part[:-2] if each else part
        following = []
        for where, value in found:
            if value is None:
                continue  # a null parent: documented at its own row
            if not isinstance(value, dict) or key not in value:
                following.append((f"{where}.{key}", KeyError))
                continue
            child = value[key]
            if each:
                if not isinstance(child, list):
                    following.append((f"{where}.{key}", TypeError))
                    continue
                following.extend((f"{where}.{key}[{i}]", item) for i, item in enumerate(child))
            else:
                following.append((f"{where}.{key}", child))
        found = following
    return found


def check(document, name, schemas, errors, where, provenance):
    rows = schemas[name] + (schemas["provenance"] if provenance else [])
    documented = {key for key, _ in rows if "." not in key and "[]" not in key}
    for key in document:
        if key not in documented:
            errors.append(f"{where}: key '{key}' is not documented in docs/json.md (`{name}`)")
    for key, types in rows:
        for at, value in values_at(document, key):
            if value is KeyError:
                errors.append(f"{where}{at}: documented in docs/json.md (`{name}`) but missing")
                continue
            if value is TypeError:
                errors.append(f"{where}{at}: not an array")
                continue
            if not any(type_ok(value, t) for t in types):
                errors.append(f"{where}{at}: {json.dumps(value)[:60]} is not {' or '.join(types)}")
                continue
            if "null" in types and isinstance(value, (int, float)) and not isinstance(value, bool) \
                    and value == 0:
                errors.append(f"{where}{at}: 0 where docs/json.md says null stands for absent")
            for t in types:
                nested = re.fullmatch(r"object: (\w+)", t)
                if nested and isinstance(value, dict):
                    check(value, nested.group(1), schemas, errors, f"{where}{at}", False)


def check_units(value, catalogue, errors, where):
    """Every `units` map agrees with the catalogue; every `parameters` map has one beside it."""
    if isinstance(value, list):
        for i, item in enumerate(value):
            check_units(item, catalogue, errors, f"{where}[{i}]")
        return
    if not isinstance(value, dict):
        return
    if isinstance(value.get("units"), dict):
        for parameter, unit in value["units"].items():
            if catalogue.get(parameter) != unit:
                errors.append(f"{where}.units.{parameter} = {unit!r}; the catalogue says "
                              f"{catalogue.get(parameter)!r}")
    if isinstance(value.get("parameters"), dict):
        units = value.get("units")
        if not isinstance(units, dict):
            errors.append(f"{where}: `parameters` without a `units` map beside it")
        else:
            for parameter in value["parameters"]:
                if parameter not in units:
                    errors.append(f"{where}.units: no unit for '{parameter}'")
    for key, item in value.items():
        check_units(item, catalogue, errors, f"{where}.{key}")


def main():
    bin_dir, source_dir, course_data, catalogue_tool = sys.argv[1:5]
    course_data = os.environ.get("ACCELCAL_COURSE_DATA") or course_data
    schemas = parse_schemas(os.path.join(source_dir, "docs", "json.md"))
    catalogue = json.loads(subprocess.run([catalogue_tool], check=True, capture_output=True,
                                          text=True).stdout)
    # Without the course data, a simulated folder of the course layout stands in for it.
    stand_in = tempfile.TemporaryDirectory()
    if not os.path.isfile(os.path.join(course_data, "ensayo.mat")):
        course_data = os.path.join(stand_in.name, "data")
        subprocess.run([os.path.join(bin_dir, "simulate"), f"--out_dir={course_data}"], check=True,
                       capture_output=True)
        print(f"no course data: measured runs read {course_data}, simulated")
    data = f"--data_dir={course_data}"
    # (schema, binary and flags, the JSON file: "json" for --json=FILE, "--flag" for --flag=FILE,
    # else a file in --out_dir)
    runs = [
        ("linear_ls", ["linear_ls", data], "json"),
        ("linear_ls", ["linear_ls", "--set=tilt_samples=500", "--ceres_max_samples=0"], "json"),
        ("trajectory", ["trajectory", data], "json"),
        ("joint", ["joint", data, "--effects=angle_offset", "--landmark=auto"], "json"),
        ("joint", ["joint", "--set=tilt_samples=500", "--effects=angle_offset,nonorthogonality",
                   "--landmark=none"], "json"),
        ("discover", ["discover", data, "--folds=0"], "json"),
        ("discover", ["discover", "--set=tilt_samples=2000,angle_offset=0.01", "--folds=2"], "json"),
        ("min_samples", ["min_samples", data, "--repetitions=0", "--design=all"], "json"),
        ("analyze", ["analyze", data, "--python=/nonexistent"], "results.json"),
        ("analyze", ["analyze", "--set=tilt_samples=2000,angle_offset=0.01", "--python=/nonexistent"],
         "results.json"),
        ("simulate", ["simulate"], "truth.json"),
        ("simulate", ["simulate", "--set=outlier_fraction=0.01,outlier_sigma=10"], "truth.json"),
        ("coverage", ["coverage", "--trials=10", "--effect_trials=10", "--set=tilt_samples=500",
                      "--threads=2"], "json"),
        ("power", ["power", "--trials=10", "--sizes=3", "--set=tilt_samples=500", "--threads=2"],
         "json"),
        ("null_rate", ["null_rate", "--datasets=10", "--designs=course", "--noise_factors=1",
                       "--alphas=0.01", "--threads=2"], "json"),
        ("calibrate", ["calibrate", data], "--calibration_out"),
        ("calibrate", ["calibrate", f"--calibration_file={course_data}/ensayo.mat"],
         "--calibration_out"),
    ]
    # The real triad sessions (../shared/data beside the course data, or the variables the
    # C++ tests read); without them their outputs cannot be checked, and the test says so.
    shared = os.path.dirname(os.path.abspath(course_data))
    imu_tk = os.environ.get("ACCELCAL_IMU_TK_DATA") or os.path.join(shared, "imu_tk-xsens")
    imucal = os.environ.get("ACCELCAL_IMUCAL_DATA") or os.path.join(shared, "imucal-ferraris")
    xsens = os.path.join(imu_tk, "xsens_acc.mat")
    session = os.path.join(imucal, "annotated_session.csv")
    runs += [
        ("triad_study", ["triad_study", "--trials=20", "--threads=2"], "json"),
        ("triad_study", ["triad_study", "--trials=20", "--pose_set=planar"], "json"),
        ("triad_study_discovery", ["triad_study", "--discovery_alpha=0.05", "--trials=10",
                                   "--poses=20", "--flicker_b=0.6", "--threads=2"], "json"),
        ("gyroscope_study", ["gyroscope_study", "--trials=10", "--discovery=0.01"], "json"),
        ("gyroscope_study", ["gyroscope_study", "--trials=10", "--turn_set=planar"], "json"),
    ]
    skipped = set()
    if os.path.isfile(xsens):
        log = [f"--log={xsens}", "--g=9.81744"]
        gyro = [f"--gyro_log={os.path.join(imu_tk, 'xsens_gyro.mat')}",
                "--initial_gyro_gain=0.000159795"]
        runs += [
            ("calibrate_imu", ["calibrate_imu"] + log, "json"),
            ("calibrate_imu", ["calibrate_imu"] + log + [
                f"--gyro_log={os.path.join(imu_tk, 'xsens_gyro.mat')}",
                "--initial_gyro_gain=0.000159795"], "json"),
            ("calibrate_imu_ml", ["calibrate_imu", "--mode=ml"] + log, "json"),
            ("calibrate_imu_ml", ["calibrate_imu", "--mode=ml", "--detector=imu_tk"] + log, "json"),
            ("calibrate_imu_ml", ["calibrate_imu", "--mode=ml", "--scale_nonlinearity"] + log,
             "json"),
            ("calibrate", ["calibrate_imu", "--mode=ml"] + log, "--calibration_out"),
            ("calibrate_imu_ml", ["calibrate_imu", "--mode=ml"] + log + gyro, "json"),
            ("calibrate", ["calibrate_imu", "--mode=ml"] + log + gyro, "--calibration_out"),
            ("allan", ["allan", f"--log={xsens}", "--bootstrap=200"], "json"),
        ]
    else:
        skipped |= {"calibrate_imu", "calibrate_imu_ml", "allan"}
        print(f"no {xsens}: calibrate_imu's outputs not checked")
    if os.path.isfile(session):
        runs += [
            ("calibrate_imu_ferraris", ["calibrate_imu", "--mode=ferraris", f"--session={session}"],
             "json"),
            ("calibrate_imu_ferraris", ["calibrate_imu", "--mode=ferraris", f"--session={session}",
                                        f"--reference={os.path.join(imucal, 'example_cal.json')}",
                                        "--sampling_rate_hz=204.8"], "json"),
        ]
    else:
        skipped.add("calibrate_imu_ferraris")
        print(f"no {session}: calibrate_imu --mode=ferraris's output not checked")
    mimu = os.environ.get("ACCELCAL_MIMU4444_DATA") or os.path.join(shared, "mimu4444")
    imu1 = [os.path.join(mimu, f"run{r}", "imu1.csv") for r in (1, 2, 3)]
    if all(os.path.isfile(f) for f in imu1):
        runs.append(("calibrate_imu_sessions",
                     ["calibrate_imu", "--log=" + ",".join(imu1), "--g=9.8187", "--mode=ml"], "json"))
        gyro = [os.path.join(mimu, f"run{r}", "imu1_acc_gyr.csv") for r in (1, 2, 3)]
        runs.append(("calibrate_imu_sessions",
                     ["calibrate_imu", "--log=" + ",".join(gyro), "--g=9.8187", "--mode=ml",
                      "--initial_gyro_gain=0.00106422515"], "json"))
    else:
        skipped.add("calibrate_imu_sessions")
        print(f"no {imu1[0]}: calibrate_imu's sessions output not checked")
    documented = {name for name in schemas if name != "provenance"} - skipped
    run_names = {name for name, _, _ in runs}
    errors = []
    if documented != run_names:
        errors.append(f"docs/json.md documents {sorted(documented)}, the test runs {sorted(run_names)}")
    for name, argv, output in runs:
        with tempfile.TemporaryDirectory() as scratch:
            if output == "json" or output.startswith("--"):
                path = os.path.join(scratch, "out.json")
                argv = argv + [f"{'--json' if output == 'json' else output}={path}"]
            else:
                path = os.path.join(scratch, "out", output)
                argv = argv + [f"--out_dir={os.path.join(scratch, 'out')}"]
            result = subprocess.run([os.path.join(bin_dir, argv[0])] + argv[1:], capture_output=True,
                                    text=True, timeout=300)
            label = " ".join(argv[:-1])
            if result.returncode != 0:
                errors.append(f"{label}: exit status {result.returncode}: {result.stderr.strip()}")
                continue
            with open(path, encoding="utf-8") as handle:
                document = json.load(handle)
        before = len(errors)
        check(document, name, schemas, errors, label + ": ", True)
        check_units(document, catalogue, errors, label + ": ")
        print(f"{label}: {'ok' if len(errors) == before else 'FAILED'}")
    stand_in.cleanup()
    for error in errors:
        print("FAIL: " + error)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
