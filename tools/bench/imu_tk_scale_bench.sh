#!/usr/bin/env bash
# accelcal beside imu_tk's own example at every size (issue 36, item 4): simulated hand-held
# sessions of an Xsens-like IMU, accelerometer and gyroscope, written as imu_tk's two ASCII files
# by build/bin/hand_held_log (50 s initial rest, holds of 3-20 s (2-3 s below 10^5 rows, where the
# rest leaves too little for a dozen longer ones) in random directions at least 30 degrees apart,
# 1.5 s turns, Xsens's noise, 100 Hz, seed fixed per size), each given to
#   imu_tk      imu_tk's apps/test_imu_calib (built from its BSD source by imu_tk_build.sh, as
#               tools/bench/imu_tk_peer.sh does: accelerometer and gyroscope, its settings)
#   imu_tk_mode calibrate_imu --mode=imu_tk with the gyroscope (imu_tk's rules; the same settings)
#   ml          calibrate_imu --mode=ml with the gyroscope (maximum likelihood of both sensors,
#               noise model, discovery with cross-validation, covariance: the default run), with
#               --calibration_out for the next two
#   apply       apply of that calibration to the accelerometer's log (corrected CSV written)
#   allan       allan --static=all on the accelerometer's log
#   floor       tools/bench's triad_bench on the accelerometer's log, one repetition: what any
#               pipeline that reads the file and makes imu_tk's accelerometer solves in Ceres
#               must spend (its "floor": the bytes read, the nine solves with the faster dense
#               solver; the gyroscope's solve is not in it)
# each a whole process under /usr/bin/time (wall, user + system CPU, peak RSS), one run per size
# (the sizes span three decades; repeat the script for spreads). Checked at every size: imu_tk's
# printed gyroscope result is the text calibrate_imu's imu_tk mode prints as imu_tk's, digit for
# digit; every program exits 0.
#
#   ACCELCAL_IMU_TK_SOURCE=PATH tools/bench/imu_tk_scale_bench.sh [ROWS ...]
#       ROWS default: 10000 100000 1000000 10000000
#
# Environment: ACCELCAL_IMU_TK_SOURCE (required, as imu_tk_peer.sh), ACCELCAL_BUILD_DIR (default
# build/), ACCELCAL_IMU_TK_BUILD (default build/imu_tk-peer), ACCELCAL_IMU_TK_MAX_ROWS (default
# 10^6: imu_tk keeps a copy of the whole gyroscope log in every turn's residual (src/calibration.cpp,
# MultiPosGyroResidual::gyro_samples_, held by value), so its memory grows as
# rows x turns, 22.9 GB at 10^6 rows; above this size it is not run and the table says so),
# ACCELCAL_SCALE_KEEP=1 keeps the temporary folder (logs and outputs; its path is printed), TMPDIR.
# Prints a table (one row per size and program), then per program the growth exponent of CPU
# time in rows (least squares on the logs, sizes from 10^5 up), and per size the ratios
# imu_tk / imu_tk_mode, imu_tk / ml (CPU and wall) and imu_tk_mode / floor (CPU).
# Exit status: 0 when every check passes; 1 when an output disagrees; 2 on a missing source,
# build or program failure.
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
say() { echo "imu_tk_scale_bench: $*" >&2; }

source "$ACCELCAL_ROOT/tools/bench/imu_tk_build.sh"
imu_tk_check_source

sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(10000 100000 1000000 10000000)
for rows in "${sizes[@]}"; do
  if ! [[ $rows =~ ^[1-9][0-9]*$ ]] || [ "$rows" -lt 10000 ]; then
    say "each size must be a number of rows >= 10000 (got '$rows')"
    exit 2
  fi
done
build=${ACCELCAL_BUILD_DIR:-$ACCELCAL_ROOT/build}
imu_tk_max_rows=${ACCELCAL_IMU_TK_MAX_ROWS:-1000000}
[ -x /usr/bin/time ] || { say "/usr/bin/time is needed (apt-get install time)"; exit 2; }

source "$ACCELCAL_ROOT/tools/setup.sh"
accelcal_install_packages libboost-dev || exit 2
for target in calibrate_imu apply allan hand_held_log triad_bench; do
  accelcal_build "$build" --target "$target" >/dev/null || exit 2
done
bin=$build/bin
imu_tk_build "${ACCELCAL_IMU_TK_BUILD:-$build/imu_tk-peer}"

work=$(mktemp -d "${TMPDIR:-/tmp}/accelcal-imu_tk-scale.XXXXXX")
if [ "${ACCELCAL_SCALE_KEEP:-0}" = 1 ]; then say "kept: $work"; else trap 'rm -rf "$work"' EXIT; fi

echo "imu_tk: test_imu_calib from $imu_tk_id, g++ $("$cxx" -dumpfullversion) ${cxxflags[*]}"
echo "accelcal: $bin ($(git -C "$ACCELCAL_ROOT" rev-parse --short HEAD)$(git -C "$ACCELCAL_ROOT" diff --quiet HEAD -- src problems tools 2>/dev/null || echo ', modified'))"
echo "machine: $(nproc) cores; load before: $(uptime | sed 's/.*load average/load average/')"

# timed NAME DIR CMD...: runs CMD in DIR under /usr/bin/time; sets wall, cpu (s), rss (MB).
timed() {
  local name=$1 dir=$2
  shift 2
  mkdir -p "$dir"
  local rc=0
  (cd "$dir" && /usr/bin/time -o "$dir/$name.time" -f '%e %U %S %M' "$@" \
    >"$dir/$name.stdout" 2>"$dir/$name.stderr" </dev/null) || rc=$?
  if [ "$rc" != 0 ]; then
    head -3 "$dir/$name.stderr" >&2
    say "$name exited with status $rc in $dir: $*"
    exit 2
  fi
  read -r wall user system kb <"$dir/$name.time"
  cpu=$(awk -v u="$user" -v s="$system" 'BEGIN { printf "%.3f", u + s }')
  rss=$(awk -v k="$kb" 'BEGIN { printf "%.1f", k / 1024 }')
}

# The gyroscope block of imu_tk's stdout, and of calibrate_imu's printout of imu_tk's text.
imu_tk_block() { awk '/^Gyroscopes calibration: residual/ { p = 1 } p && /^$/ { exit } p' "$1"; }
accelcal_block() {
  awk '/^  Gyroscopes calibration: residual/ { p = 1 } p && /^$/ { exit } p' "$1" | sed 's/^  //'
}

failures=0
results=$work/results.txt
: >"$results"
printf '%10s %6s  %-12s %9s %9s %9s\n' rows poses program "wall s" "CPU s" "RSS MB"
for rows in "${sizes[@]}"; do
  dir=$work/$rows
  mkdir -p "$dir"
  # Below 10^5 rows the 50 s rest leaves too little for 12 holds of 3-20 s: holds of 2-3 s.
  holds=()
  [ "$rows" -lt 100000 ] && holds=(--hold_min_s=2 --hold_max_s=3)
  "$bin/hand_held_log" --rows="$rows" --seed="$rows" --acc_out="$dir/acc.txt" \
    --gyro_out="$dir/gyro.txt" "${holds[@]}" >"$dir/generate.txt"
  common=(--log="$dir/acc.txt" --gyro_log="$dir/gyro.txt" --g=9.81744 --init_rest_s=50
    --initial_gyro_gain=0.00015979546180888463)
  run_imu_tk=1
  if [ "$rows" -gt "$imu_tk_max_rows" ]; then
    run_imu_tk=0
    say "$rows rows: imu_tk's example not run (above ACCELCAL_IMU_TK_MAX_ROWS=$imu_tk_max_rows: its memory grows as the turns times the rows, 22.9 GB at 10^6 rows here)"
  else
    timed imu_tk "$dir/imu_tk" "$imu_tk_bin" "$dir/acc.txt" "$dir/gyro.txt"
    echo "$rows imu_tk $wall $cpu $rss" >>"$results"
  fi
  timed imu_tk_mode "$dir/imu_tk_mode" "$bin/calibrate_imu" "${common[@]}" --mode=imu_tk \
    --initial_offset=32768
  echo "$rows imu_tk_mode $wall $cpu $rss" >>"$results"
  if [ "$run_imu_tk" = 1 ] && [ "$(imu_tk_block "$dir/imu_tk/imu_tk.stdout")" != \
    "$(accelcal_block "$dir/imu_tk_mode/imu_tk_mode.stdout")" ]; then
    say "FAIL at $rows rows: imu_tk's gyroscope lines differ from calibrate_imu's printout of them"
    failures=$((failures + 1))
  fi
  timed ml "$dir/ml" "$bin/calibrate_imu" "${common[@]}" --mode=ml --calibration_out="$dir/cal.json"
  echo "$rows ml $wall $cpu $rss" >>"$results"
  poses=$(sed -n 's/^poses: the \([0-9]*\) static intervals.*/\1/p' "$dir/ml/ml.stdout" | head -1)
  echo "$rows poses $poses" >>"$results"
  timed apply "$dir/apply" "$bin/apply" --calibration="$dir/cal.json" --in="$dir/acc.txt" \
    --out="$dir/corrected.csv"
  echo "$rows apply $wall $cpu $rss" >>"$results"
  rm -f "$dir/corrected.csv"
  timed allan "$dir/allan" "$bin/allan" --log="$dir/acc.txt" --static=all
  echo "$rows allan $wall $cpu $rss" >>"$results"
  timed floor "$dir/floor" "$bin/triad_bench" --log="$dir/acc.txt" --repetitions=1 \
    --json="$dir/floor.json"
  floor_cpu=$(/usr/bin/python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["timing"]["floor"]["cpu_seconds"])' "$dir/floor.json")
  echo "$rows floor - $floor_cpu -" >>"$results"
  for program in imu_tk imu_tk_mode ml apply allan floor; do
    awk -v r="$rows" -v p="$program" -v n="${poses:-?}" '$1 == r && $2 == p {
      printf "%10d %6s  %-12s %9s %9s %9s\n", r, n, p, $3, $4, $5 }' "$results"
  done
  rm -f "$dir/acc.txt" "$dir/gyro.txt"
done
echo "load after: $(uptime | sed 's/.*load average/load average/')"

echo
echo "growth exponent of CPU time in rows (least squares on the logs, sizes >= 10^5):"
for program in imu_tk imu_tk_mode ml apply allan floor; do
  awk -v p="$program" '$2 == p && $1 >= 100000 && $4 > 0 {
      x = log($1); y = log($4); n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
    END { if (n >= 2) printf "  %-12s %.2f (%d sizes)\n", p, (n * sxy - sx * sy) / (n * sxx - sx * sx), n;
          else printf "  %-12s (fewer than two sizes >= 10^5)\n", p }' "$results"
done
echo
echo "ratios per size: imu_tk / imu_tk_mode, imu_tk / ml (CPU; wall in brackets); imu_tk_mode / floor (CPU)"
for rows in "${sizes[@]}"; do
  awk -v r="$rows" '$1 == r { w[$2] = $3; c[$2] = $4 } END {
    if ("imu_tk" in c)
      printf "  %10d  imu_tk/imu_tk_mode %6.2f (%5.2f)   imu_tk/ml %6.2f (%5.2f)   imu_tk_mode/floor %6.2f\n",
        r, c["imu_tk"] / c["imu_tk_mode"], w["imu_tk"] / w["imu_tk_mode"], c["imu_tk"] / c["ml"],
        w["imu_tk"] / w["ml"], c["imu_tk_mode"] / c["floor"];
    else
      printf "  %10d  imu_tk not run                                                 imu_tk_mode/floor %6.2f\n",
        r, c["imu_tk_mode"] / c["floor"] }' "$results"
done
if [ "$failures" -gt 0 ]; then
  say "$failures checks failed (FAIL lines above)"
  exit 1
fi
say "check: at every size imu_tk's printed gyroscope result = calibrate_imu's imu_tk mode's printout of it"
