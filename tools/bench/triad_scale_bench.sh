#!/usr/bin/env bash
# calibrate_imu --mode=ml at scale (issue 36): synthetic hand-held logs of 10^5 to 10^6 rows (or
# the sizes given), 100 Hz, holds of 3-20 s (uniform) in random directions at least 30 deg apart,
# 1.5 s turns between them with a (1 - cos) profile, a triad of ~4000 counts/g with offsets near
# 32768, off-diagonal angles of a few mrad, 3 counts of white noise, rounded to counts. The logs
# are written by tools/bench/hand_held_log.py (Debian's /usr/bin/python3 with numpy; the same
# generator as stream_scale_bench.sh's) to a temporary folder, imu_tk's ASCII layout (t x y z),
# seed fixed per size. Up to 10^6 rows its logs are byte for byte those of the generator this
# script embedded before; above, it draws the noise per 10^6-row piece, so they differ by seed.
#
# Each size: calibrate_imu --mode=ml (discovery, determination and covariance included: the
# default run) timed as a whole process by /usr/bin/time -v: wall time, CPU time (user + system)
# and peak RSS; then the growth exponent of wall and CPU time in the pose count (least squares on
# the logs, over the sizes from the second one up: the smallest is dominated by the start-up).
#
#   tools/bench/triad_scale_bench.sh [BIN_DIR] [ROWS ...]
#       BIN_DIR: default build/bin (calibrate_imu is not built here); ROWS default
#       100000 200000 500000 1000000
# Environment: ACCELCAL_SCALE_KEEP=1 keeps the temporary folder (its path is printed).
# Prints one table row per size: rows, poses (the poses calibrate_imu used), wall s, CPU s,
# peak RSS MB, exit status; then `exponent cpu=X wall=Y`.
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin_dir=${1:-$ACCELCAL_ROOT/build/bin}
shift || true
sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(100000 200000 500000 1000000)
python=/usr/bin/python3
say() { echo "triad_scale_bench: $*" >&2; }
[ -x "$bin_dir/calibrate_imu" ] || { say "no $bin_dir/calibrate_imu"; exit 2; }
[ -x /usr/bin/time ] || { say "/usr/bin/time is needed (apt-get install time)"; exit 2; }
"$python" -c 'import numpy' 2>/dev/null || { say "$python with numpy is needed"; exit 2; }

generate=$ACCELCAL_ROOT/tools/bench/hand_held_log.py
work=$(mktemp -d "${TMPDIR:-/tmp}/accelcal-triad-scale.XXXXXX")
if [ "${ACCELCAL_SCALE_KEEP:-0}" = 1 ]; then say "logs kept in $work"; else trap 'rm -rf "$work"' EXIT; fi


printf '%-9s %6s %9s %9s %9s %4s\n' rows poses wall_s cpu_s rss_MB rc
results=()
for rows in "${sizes[@]}"; do
  log="$work/hand_held_$rows.txt"
  "$python" "$generate" "$rows" "$log" "$rows"
  set +e
  /usr/bin/time -v -o "$work/time_$rows.txt" "$bin_dir/calibrate_imu" --log="$log" --g=9.81 \
      --mode=ml --json="$work/ml_$rows.json" >"$work/out_$rows.txt" 2>&1
  rc=$?
  set -e
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, p, ":"); s = 0;
           for (i = 1; i <= n; ++i) s = s * 60 + p[i]; print s}' "$work/time_$rows.txt")
  cpu=$(awk -F': ' '/User time/ {u = $2} /System time/ {s = $2} END {print u + s}' "$work/time_$rows.txt")
  rss=$(awk -F': ' '/Maximum resident/ {printf "%.0f", $2 / 1024}' "$work/time_$rows.txt")
  poses=$(sed -n 's/^poses: the \([0-9]*\) static intervals.*/\1/p' "$work/out_$rows.txt" | head -1)
  [ -n "$poses" ] || poses="?"
  printf '%-9s %6s %9.2f %9.2f %9s %4s\n' "$rows" "$poses" "$wall" "$cpu" "$rss" "$rc"
  results+=("$poses $wall $cpu")
done
printf '%s\n' "${results[@]}" | "$python" -c '
import sys, numpy as np
r = [l.split() for l in sys.stdin if l.strip()]
r = [(float(p), float(w), float(c)) for p, w, c in r if p not in ("?", "None")]
if len(r) >= 3: r = r[1:]
if len(r) < 2: sys.exit(0)
p = np.log([x[0] for x in r])
fit = lambda y: np.polyfit(p, np.log(y), 1)[0]
print("exponent cpu=%.2f wall=%.2f (in poses, %d sizes)" % (fit([x[2] for x in r]), fit([x[1] for x in r]), len(r)))'
