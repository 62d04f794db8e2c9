#!/usr/bin/env bash
# apply and allan at scale (issue 36, item 2): synthetic hand-held logs of 10^5 to 10^7 rows (or
# the sizes given), the generator of tools/bench/triad_scale_bench.sh (100 Hz, holds of 3-20 s in
# random directions, 1.5 s turns, ~4000 counts/g, 3 counts of white noise, imu_tk's ASCII layout
# t x y z), written by an embedded numpy script (Debian's /usr/bin/python3) to a temporary folder.
#
# A calibration is made once, by calibrate_imu --mode=ml on the smallest log. Then, per size,
# each timed as a whole process by /usr/bin/time -v (wall time, CPU time = user + system, peak
# RSS):
#   apply       apply --calibration=CAL --in=LOG --out=OUT
#   read+write  the reference: the time to read the log and write a file of apply's output's
#               size, measured as `cat LOG >/dev/null; cat OUT > COPY` (block copies, the
#               floor of any reader and writer; the output is some 5 times the log's size)
#   parse+fmt   the reference of text: build/bin/text_io_floor reads the log with apply's reader
#               and writes rows of apply's shape and number format (no correction, checks,
#               checksum or temporary file), the floor of any apply that reads and writes text
#   allan       allan --log=LOG --unit=count --static=all
# and the growth exponents of each in the rows (least squares on the logs over all sizes), and
# apply's time over each reference's.
#
#   tools/bench/stream_scale_bench.sh [BIN_DIR] [ROWS ...]
#       BIN_DIR: default build/bin; ROWS default 100000 1000000 10000000
# Environment: ACCELCAL_SCALE_KEEP=1 keeps the temporary folder (its path is printed);
# ACCELCAL_STREAM_SKIP_ALLAN=1 leaves allan out.
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin_dir=${1:-$ACCELCAL_ROOT/build/bin}
shift || true
sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(100000 1000000 10000000)
python=/usr/bin/python3
say() { echo "stream_scale_bench: $*" >&2; }
for binary in apply allan calibrate_imu text_io_floor; do
  [ -x "$bin_dir/$binary" ] || { say "no $bin_dir/$binary"; exit 2; }
done
[ -x /usr/bin/time ] || { say "/usr/bin/time is needed (apt-get install time)"; exit 2; }
"$python" -c 'import numpy' 2>/dev/null || { say "$python with numpy is needed"; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/accelcal-stream-scale.XXXXXX")
if [ "${ACCELCAL_SCALE_KEEP:-0}" = 1 ]; then say "logs kept in $work"; else trap 'rm -rf "$work"' EXIT; fi

generate=$ACCELCAL_ROOT/tools/bench/hand_held_log.py

# /usr/bin/time -v's wall s, CPU s and peak RSS MB of its report $1.
measure() {
  awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, p, ":"); w = 0;
                for (i = 1; i <= n; ++i) w = w * 60 + p[i]}
              /User time/ {u = $2} /System time/ {s = $2}
              /Maximum resident/ {r = $2 / 1024}
              END {printf "%.2f %.2f %.0f", w, u + s, r}' "$1"
}

# Runs the command after `--` under /usr/bin/time -v, its output to $2.out; prints
# "wall cpu rss rc".
timed() {
  local name=$1 dir=$2
  shift 2
  set +e
  /usr/bin/time -v -o "$dir/$name.time" "$@" >"$dir/$name.out" 2>&1
  local rc=$?
  set -e
  echo "$(measure "$dir/$name.time") $rc"
}

smallest=${sizes[0]}
for rows in "${sizes[@]}"; do
  [ "$rows" -lt "$smallest" ] && smallest=$rows
done
"$python" "$generate" "$smallest" "$work/calibration_log.txt" 1
"$bin_dir/calibrate_imu" --log="$work/calibration_log.txt" --g=9.81 --mode=ml \
    --calibration_out="$work/cal.json" >"$work/calibrate.out" 2>&1 ||
  { say "calibrate_imu failed: $(tail -1 "$work/calibrate.out")"; exit 2; }

printf '%-9s %-10s %9s %9s %9s %4s\n' rows step wall_s cpu_s rss_MB rc
results=()
for rows in "${sizes[@]}"; do
  log="$work/hand_held_$rows.txt"
  "$python" "$generate" "$rows" "$log" "$rows"
  read -r wall cpu rss rc < <(timed "apply_$rows" "$work" "$bin_dir/apply" \
      --calibration="$work/cal.json" --in="$log" --out="$work/corrected_$rows.csv")
  printf '%-9s %-10s %9s %9s %9s %4s\n' "$rows" apply "$wall" "$cpu" "$rss" "$rc"
  results+=("$rows apply $wall $cpu $rss")
  read -r wall cpu rss rc < <(timed "copy_$rows" "$work" sh -c 'cat "$1" >/dev/null; cat "$2" >"$3"' \
      copy "$log" "$work/corrected_$rows.csv" "$work/copy_$rows.csv")
  printf '%-9s %-10s %9s %9s %9s %4s\n' "$rows" read+write "$wall" "$cpu" "$rss" "$rc"
  results+=("$rows copy $wall $cpu $rss")
  rm -f "$work/corrected_$rows.csv" "$work/copy_$rows.csv"
  read -r wall cpu rss rc < <(timed "floor_$rows" "$work" "$bin_dir/text_io_floor" \
      --log="$log" --out="$work/floor_$rows.csv")
  printf '%-9s %-10s %9s %9s %9s %4s\n' "$rows" parse+fmt "$wall" "$cpu" "$rss" "$rc"
  results+=("$rows floor $wall $cpu $rss")
  rm -f "$work/floor_$rows.csv"
  if [ "${ACCELCAL_STREAM_SKIP_ALLAN:-0}" != 1 ]; then
    read -r wall cpu rss rc < <(timed "allan_$rows" "$work" "$bin_dir/allan" --log="$log" \
        --unit=count --static=all)
    printf '%-9s %-10s %9s %9s %9s %4s\n' "$rows" allan "$wall" "$cpu" "$rss" "$rc"
    results+=("$rows allan $wall $cpu $rss")
  fi
  rm -f "$log"
done
printf '%s\n' "${results[@]}" | "$python" -c '
import sys, numpy as np
rows = {}
for line in sys.stdin:
    n, step, wall, cpu, rss = line.split()
    rows.setdefault(step, []).append((float(n), float(wall), float(cpu), float(rss)))
for step, r in rows.items():
    if len(r) < 2:
        continue
    x = np.log([v[0] for v in r])
    fit = lambda y: np.polyfit(x, np.log(np.maximum(y, 1e-3)), 1)[0]
    print("exponent %-10s wall=%.2f cpu=%.2f rss=%.2f (in rows, %d sizes)" % (
        step, fit([v[1] for v in r]), fit([v[2] for v in r]), fit([v[3] for v in r]), len(r)))
copy = {v[0]: v[1] for v in rows.get("copy", [])}
floor = {v[0]: (v[1], v[2]) for v in rows.get("floor", [])}
for n, wall, cpu, _ in rows.get("apply", []):
    if copy.get(n, 0) > 0:
        print("apply / read+write at %d rows: %.2f (wall)" % (n, wall / copy[n]))
    if n in floor and floor[n][0] > 0 and floor[n][1] > 0:
        print("apply / parse+fmt at %d rows: %.2f (wall), %.2f (CPU)" % (
            n, wall / floor[n][0], cpu / floor[n][1]))'
