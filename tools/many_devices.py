#!/usr/bin/python3
"""Calibrate a folder of IMU logs, one per device (or session), in parallel with Dask.

Each log is one task of Dask's scheduler: accelcal.calibrate (the Python module, docs/python.md;
calibrate_imu --mode=ml's sequence) on the worker, which returns the calibration file's text and
one row of the summary. On a single machine the tasks run on a LocalCluster of --workers
processes; on a cluster, on the workers of the scheduler at --scheduler (docs/many-devices.md).
The logs must be readable by the workers at the same path; the outputs are written by this
process alone, so the workers need no access to --out.

Outputs, in --out (created; an existing one replaced only with --overwrite, and only when
accelcal wrote it, i.e. it carries the .accelcal-output marker):
  <device>.calibration.json   one per device that calibrated (apply reads it)
  summary.csv                 one row per log: device, file, sha256, poses, verdict, chi2/dof,
                              the gains and offsets with their sigma, or the failure's message
and the same table on stdout. A log that fails (unreadable, too few poses, ...) is a row with
its message, not the end of the others. Nothing partial: the files are written into a new
folder beside --out, which replaces --out only when every file is written. --out is checked
before any work by the binaries' own rules (the module's check_output and write_folder, i.e.
io/output_paths.h and io/atomic_file.h): it may not be, hold or lie inside an input (the logs
folder, a log), nor be a file, a link or a special file; a refusal is one line on stderr, exit
status 2, and nothing is written.

  /usr/bin/python3 tools/many_devices.py --logs='logs/*.csv' --out=calibrations --workers=2 \\
      --g=9.81 [--scheduler=tcp://host:8786] [--unit=count] [--alpha=0.01]

Exit status: 0 when every device calibrated; 1 when the run completed but some device failed (its
row says why; the others' outputs are written); 2 on bad arguments (the options are checked by
calibrate_imu's own rules before any work), an --out that may not be written, when no log
matched, or when the outputs could not be written (the old --out then left as it was).
"""
import argparse
import csv
import glob
import io
import os
import sys
import time

# The summary's columns, in order; gains in (m/s^2) per unit of the log, offsets in its unit.
AXES = ("x", "y", "z")
PARAMETERS = [f"gain_{a}" for a in AXES] + [f"offset_{a}" for a in AXES]
COLUMNS = (["device", "file", "sha256", "status", "poses", "verdict", "chi2", "dof", "chi2_dof"] +
           [c for p in PARAMETERS for c in (p, p + "_sigma")] +
           ["unit", "calibration_file", "seconds", "message"])


def calibrate_device(path, options):
    """One task: the log's calibration, as (row, calibration file text or None). Runs on a
    worker; every failure becomes the row's message."""
    import accelcal  # on the worker

    device = device_name(path)
    row = {"device": device, "file": path, "status": "failed"}
    start = time.perf_counter()
    try:
        log = accelcal.read_log(path)
        row["sha256"] = log.sha256
        cal = accelcal.calibrate(log, **options)
        text = cal.file_text()
    except Exception as error:  # accelcal.Error (bad input) and anything else: one row
        row["message"] = f"{type(error).__name__}: {error}" if not isinstance(
            error, ValueError) else str(error)
        row["seconds"] = f"{time.perf_counter() - start:.3f}"
        return row, None
    row.update(status="ok", poses=cal.poses, verdict=cal.verdict_kind, chi2=repr(cal.chi2),
               dof=cal.dof, chi2_dof=f"{cal.chi2 / cal.dof:.4g}" if cal.dof > 0 else "",
               unit=cal.unit, calibration_file=device + ".calibration.json",
               seconds=f"{time.perf_counter() - start:.3f}", message="")
    for name, value, sigma in zip(cal.names, cal.values, cal.stddev):
        if name in PARAMETERS:
            row[name] = repr(float(value))
            row[name + "_sigma"] = repr(float(sigma))
    return row, text


def device_name(path):
    base = os.path.basename(path)
    for suffix in (".csv", ".txt", ".mat", ".log"):
        if base.lower().endswith(suffix):
            return base[: -len(suffix)]
    return base


def find_logs(pattern):
    if os.path.isdir(pattern):
        paths = [os.path.join(pattern, n) for n in os.listdir(pattern)]
        paths = [p for p in paths if os.path.isfile(p)]
    else:
        paths = [p for p in glob.glob(pattern) if os.path.isfile(p)]
    return sorted(os.path.abspath(p) for p in paths)


def summary_csv(rows):
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({c: row.get(c, "") for c in COLUMNS})
    return out.getvalue()


def printed_table(rows):
    def pm(row, name, digits):
        if row.get("status") != "ok":
            return ""
        return f"{float(row[name]):.{digits}g} +- {float(row[name + '_sigma']):.2g}"

    lines = [f"{'device':<16} {'poses':>5} {'verdict':<17} {'chi2/dof':>8}  "
             f"{'gain_x':<24} {'gain_y':<24} {'gain_z':<24} {'offset_x':<20} {'offset_y':<20} "
             f"{'offset_z':<20}"]
    for row in rows:
        if row.get("status") != "ok":
            lines.append(f"{row['device']:<16} failed: {row.get('message', '')}")
            continue
        lines.append(f"{row['device']:<16} {row['poses']:>5} {row['verdict']:<17} "
                     f"{row['chi2_dof']:>8}  " +
                     " ".join(f"{pm(row, 'gain_' + a, 6):<24}" for a in AXES) + " " +
                     " ".join(f"{pm(row, 'offset_' + a, 7):<20}" for a in AXES))
    return "\n".join(lines) + "\n"


def write_outputs(out_dir, files, inputs=(), input_folders=(), overwrite=False):
    """Writes `files` (name -> text) as the folder out_dir, whole or not at all: the module's
    write_folder (io/atomic_file.h's WriteDirectoryAtomically, the binaries' writer) fills a new
    folder beside it, with accelcal's marker, and swaps it in; on any failure the temporary
    folder is removed and out_dir left as it was. It replaces an existing out_dir only with
    `overwrite` and only when accelcal wrote it, and never one that is, holds or lies inside an
    input. Raises accelcal.Error."""
    import accelcal

    accelcal.write_folder(out_dir, files, inputs=list(inputs), input_folders=list(input_folders),
                          overwrite=overwrite, flag="--out")


def parse_args(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--logs", required=True,
                        help="A folder (every file in it) or a glob of logs, one per device")
    parser.add_argument("--out", required=True, help="The folder of the outputs")
    parser.add_argument("--overwrite", action="store_true", help="Replace an existing --out")
    parser.add_argument("--scheduler", default="",
                        help="A Dask scheduler's address (tcp://host:8786); none: a LocalCluster")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1,
                        help="LocalCluster: worker processes (default: the CPU count)")
    parser.add_argument("--threads_per_worker", type=int, default=1,
                        help="LocalCluster: threads per worker (the module releases the GIL)")
    parser.add_argument("--g", type=float, default=9.81, help="Local gravity, m/s^2")
    parser.add_argument("--unit", default=None, help="count, m/s^2 or g (default: the columns' "
                        "names, else count)")
    parser.add_argument("--alpha", type=float, default=0.01, help="Discovery's error rate")
    parser.add_argument("--noise", default="auto", help="white, allan or auto")
    args = parser.parse_args(argv)
    if args.workers < 1 or args.threads_per_worker < 1:
        parser.error("--workers and --threads_per_worker must be at least 1")
    return args


def main(argv):
    args = parse_args(argv)
    paths = find_logs(args.logs)
    if not paths:
        print(f"many_devices: error: no log matches --logs={args.logs}", file=sys.stderr)
        return 2
    names = [device_name(p) for p in paths]
    if len(set(names)) != len(names):
        print("many_devices: error: two logs give the same device name (their file names "
              "without the suffix); rename one", file=sys.stderr)
        return 2
    try:
        import accelcal
    except ImportError as error:
        print(f"many_devices: error: cannot import the module accelcal ({error}): build and "
              "register it (docs/python.md)", file=sys.stderr)
        return 2
    # The outputs' rules, checked before any work (nothing is written on a refusal): the
    # binaries' guard, with the logs and, for --logs=FOLDER, that folder as the inputs.
    input_folders = [args.logs] if os.path.isdir(args.logs) else []
    try:
        accelcal.check_output(args.out, kind="folder", inputs=paths, input_folders=input_folders,
                              overwrite=args.overwrite, flag="--out")
    except accelcal.Error as error:
        print(f"many_devices: error: {error}", file=sys.stderr)
        return 2
    options = {"g": args.g, "unit": args.unit, "alpha": args.alpha, "noise": args.noise}
    # The options by calibrate_imu's rules, once, before any work: a bad --g is one refusal, not
    # one failed row per device.
    try:
        accelcal.check_options(g=args.g, alpha=args.alpha)
    except accelcal.Error as error:
        print(f"many_devices: error: {error}", file=sys.stderr)
        return 2

    from dask.distributed import Client, LocalCluster

    start = time.perf_counter()
    if args.scheduler:
        client = Client(args.scheduler)
        cluster = None
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=args.threads_per_worker,
                               processes=True, dashboard_address=None)
        client = Client(cluster)
    started = time.perf_counter()
    try:
        futures = client.map(calibrate_device, paths, options=options, pure=False)
        results = client.gather(futures)
        compute = time.perf_counter() - started
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    wall = time.perf_counter() - start

    rows = [row for row, _ in results]
    files = {row["calibration_file"]: text for row, text in results if text is not None}
    files["summary.csv"] = summary_csv(rows)
    try:
        write_outputs(args.out, files, inputs=paths, input_folders=input_folders,
                      overwrite=args.overwrite)
    except accelcal.Error as error:
        print(f"many_devices: error: {error}", file=sys.stderr)
        return 2
    ok = sum(row["status"] == "ok" for row in rows)
    sys.stdout.write(printed_table(rows))
    where = (f"scheduler {args.scheduler}" if args.scheduler else
             f"{args.workers} local worker(s) x {args.threads_per_worker} thread(s)")
    task_seconds = sum(float(row.get("seconds") or 0) for row in rows)
    print(f"{ok} of {len(rows)} devices calibrated in {wall:.1f} s on {where}: "
          f"{started - start:.1f} s to start, {compute:.1f} s for the tasks "
          f"({task_seconds:.1f} s inside them); outputs in {os.path.abspath(args.out)}")
    if ok < len(rows):
        print(f"many_devices: {len(rows) - ok} of {len(rows)} devices failed (see their rows)",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
