#!/usr/bin/env bash
# The triad benchmark (issue 20): calibrate_imu's pipeline on imu_tk's Xsens log (read,
# imu_tk's detector and k = 2..10 sweep, the maximum-likelihood fit with covariance) timed
# in-process by accelcal (tools/bench/triad_bench.cc) and by numpy/SciPy
# (tools/bench/triad_scipy.py, Debian's /usr/bin/python3), in the same run, every estimate
# checked to agree. Prints the checks, both sides' median time per stage, the ratio, and ends
# with `speedup total=X` when everything agrees.
#
#   tools/bench/triad_bench.sh [BIN_DIR]        # BIN_DIR: default build/bin
#
# Builds nothing (build triad_bench first). Environment: ACCELCAL_IMU_TK_DATA (default
# ../shared/data/imu_tk-xsens), ACCELCAL_TRIAD_REPETITIONS (default 21 per side),
# ACCELCAL_TRIAD_MIN_RATIO (default 10), ACCELCAL_TRIAD_MALLOC_TUNING (default 1, below).
# Prints, after the stages, the floor of any pipeline that keeps imu_tk's nine fits in Ceres
# (the file's bytes read, nothing parsed, plus the nine solves; docs/performance.md).
# Exit status: 0 when the estimates agree and numpy/SciPy's total time is at least
# MIN_RATIO times accelcal's; 1 when an estimate disagrees; 3 when they agree but the ratio is
# below MIN_RATIO; 2 when the binary, the interpreter or the data is missing.
#
# Malloc tuning: on this project's VMs (Firecracker) a first touch of a fresh page costs about
# 8 us, some 40 times a bare-metal fault, and glibc hands each new array above 128 KiB fresh
# pages from mmap; numpy, which makes a new array per operation, spends most of its time in
# page faults (measured: the sliding variance, 2,200 faults and 63 ms per call, 7.6 ms
# without them). That is the sandbox, not numpy, so both sides run with glibc's heap kept
# (MALLOC_MMAP_THRESHOLD_ and MALLOC_TRIM_THRESHOLD_ at 1 GB). ACCELCAL_TRIAD_MALLOC_TUNING=0
# runs both with glibc's defaults instead.
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)

bin_dir=${1:-$ACCELCAL_ROOT/build/bin}
data=${ACCELCAL_IMU_TK_DATA:-$ACCELCAL_ROOT/../shared/data/imu_tk-xsens}
repetitions=${ACCELCAL_TRIAD_REPETITIONS:-21}
min_ratio=${ACCELCAL_TRIAD_MIN_RATIO:-10}
python=/usr/bin/python3
log=$data/xsens_acc.mat
# imu_tk's Xsens example: its g, initial rest and initial offsets.
configuration=(--g=9.81744 --init_rest_s=50 --initial_offset=32768)

say() { echo "triad_bench: $*" >&2; }

if [ ! -x "$bin_dir/triad_bench" ]; then
  say "no $bin_dir/triad_bench; build it (cmake --build build --target triad_bench)"
  exit 2
fi
if [ ! -x "$python" ] || ! "$python" -c 'import numpy, scipy' 2>/dev/null; then
  say "$python with numpy and scipy is needed (apt-get install python3-numpy python3-scipy)"
  exit 2
fi
if [ ! -f "$log" ]; then
  say "no imu_tk log at $log; set ACCELCAL_IMU_TK_DATA to the imu_tk-xsens folder"
  exit 2
fi
if [ "${ACCELCAL_TRIAD_MALLOC_TUNING:-1}" != 0 ]; then
  export MALLOC_MMAP_THRESHOLD_=1073741824 MALLOC_TRIM_THRESHOLD_=1073741824
  malloc="glibc heap kept (MALLOC_MMAP_THRESHOLD_, MALLOC_TRIM_THRESHOLD_ = 1 GB)"
else
  malloc="glibc's default malloc thresholds"
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/accelcal-triad-bench.XXXXXX")
trap 'rm -rf "$work"' EXIT

echo "triad benchmark: $log, $repetitions repetitions per side, 1 thread, $malloc"
echo "load before: $(uptime | sed 's/.*load average/load average/')"
"$bin_dir/triad_bench" --log="$log" "${configuration[@]}" --repetitions="$repetitions" \
  --json="$work/accelcal.json"
status=0
"$python" "$ACCELCAL_ROOT/tools/bench/triad_scipy.py" --log="$log" "${configuration[@]}" \
  --repetitions="$repetitions" --accelcal_json="$work/accelcal.json" \
  --min_ratio="$min_ratio" || status=$?
echo "load after: $(uptime | sed 's/.*load average/load average/')"
case $status in
  0) ;;
  1) say "the estimates disagree (FAIL lines above)" ;;
  3) say "the estimates agree, but numpy/SciPy's total is less than $min_ratio times accelcal's" ;;
  *) say "triad_scipy.py failed (status $status)" ;;
esac
exit "$status"
