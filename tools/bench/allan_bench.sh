#!/usr/bin/env bash
# allan on one still log (issue 49, item 1: "Allan variance at the floor"): a simulated still
# accelerometer log of ROWS samples at RATE_HZ (build/bin/allan_still_log: one rest, counts about
# 32768, 3.2 counts of white noise and a slow random walk, imu_tk's ASCII layout t x y z),
# written to a temporary folder under $TMPDIR (never the repository), then, each timed as a
# whole process by /usr/bin/time -v (wall time, CPU time = user + system, peak RSS):
#   parse   the floor: build/bin/text_io_floor --log=LOG --parse_only reads the same file with
#           the reader allan uses (StreamImuLog, the same batches) and nothing else
#   allan   allan --log=LOG --unit=count --json=OUT.json (the default --static=longest: the
#           detector, the Allan variance of the one long segment, the bootstrap of 1000 series)
# Prints each command with its figures, and allan's CPU time over the floor's.
#
#   tools/bench/allan_bench.sh [BIN_DIR] [ROWS] [RATE_HZ]
#       BIN_DIR default build/bin; ROWS default 2160000 (3 h at 200 Hz); RATE_HZ default 200
#   tools/bench/allan_bench.sh build/bin 100000000 1000     # a day at 1 kHz: 2.7 GB of text
# Environment: ACCELCAL_ALLAN_BENCH_KEEP=1 keeps the temporary folder (its path is printed).
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin_dir=${1:-$ACCELCAL_ROOT/build/bin}
rows=${2:-2160000}
rate_hz=${3:-200}
say() { echo "allan_bench: $*" >&2; }
for binary in allan allan_still_log text_io_floor; do
  [ -x "$bin_dir/$binary" ] || { say "no $bin_dir/$binary (build the targets allan, allan_still_log, text_io_floor)"; exit 2; }
done
[ -x /usr/bin/time ] || { say "/usr/bin/time is needed (apt-get install time)"; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/accelcal-allan-bench.XXXXXX")
if [ "${ACCELCAL_ALLAN_BENCH_KEEP:-0}" = 1 ]; then
  say "files kept in $work"
else
  trap 'rm -rf "$work"' EXIT
fi

# /usr/bin/time -v's wall s, CPU s (user + system) and peak RSS MB of its report $1.
measure() {
  awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, p, ":"); w = 0;
                for (i = 1; i <= n; ++i) w = w * 60 + p[i]}
              /User time/ {u = $2} /System time/ {s = $2}
              /Maximum resident/ {r = $2 / 1024}
              END {printf "%.2f %.2f %.0f\n", w, u + s, r}' "$1"
}

# Runs the command after the name under /usr/bin/time -v (its output to $work/NAME.out), prints
# the command and "wall cpu rss" on one line; exit 2 when it fails.
timed() {
  local name=$1
  shift
  set +e
  /usr/bin/time -v -o "$work/$name.time" "$@" >"$work/$name.out" 2>"$work/$name.err"
  local rc=$?
  set -e
  if [ "$rc" -ne 0 ]; then
    say "$name failed (exit $rc): $(tail -1 "$work/$name.err")"
    exit 2
  fi
  read -r wall cpu rss < <(measure "$work/$name.time")
  printf '%-6s wall %8.2f s  CPU %8.2f s  max RSS %6s MB   %s\n' "$name" "$wall" "$cpu" "$rss" "$*"
  eval "${name}_cpu=$cpu"
}

log="$work/still_$rows.txt"
"$bin_dir/allan_still_log" --rows="$rows" --rate_hz="$rate_hz" --out="$log" >/dev/null
echo "allan_bench: $rows samples at $rate_hz Hz, $(du -m "$log" | cut -f1) MB of text; $(nproc) cores, $(cut -d' ' -f1-3 /proc/loadavg) load"
timed parse "$bin_dir/text_io_floor" --log="$log" --parse_only
timed allan "$bin_dir/allan" --log="$log" --unit=count --json="$work/allan.json"
awk -v a="$allan_cpu" -v p="$parse_cpu" \
  'BEGIN {if (p > 0) printf "allan / parse floor (CPU): %.1f\n", a / p}'
