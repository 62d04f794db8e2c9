#!/usr/bin/env bash
# accelcal beside the tools a researcher would otherwise use (issue 9): the baseline and the
# joint solve timed in-process by accelcal (tools/bench/peer_timing.cc) and by numpy/SciPy
# (tools/bench/peers.py, Debian's /usr/bin/python3), on the course data and on a simulated
# tilt test of 10^7 samples, with every estimate checked to agree. Prints one table and ends
# with `speedup baseline=X joint=Y`: numpy/SciPy time over accelcal time on the course data
# (ratio of the medians; the closed-form baseline against numpy.linalg.lstsq, the joint solve
# with covariance against scipy.optimize.least_squares with an analytic Jacobian).
#
#   ./tools/test.sh && tools/bench/peers.sh
#
# Environment: ACCELCAL_COURSE_DATA (default ../shared/data/tp2-2018), ACCELCAL_BUILD_DIR
# (default build/, as tools/test.sh makes it), ACCELCAL_PEERS_SAMPLES (the simulated test's
# size, default 10000000). On the 10^7 test accelcal runs its closed-form baseline and its
# joint solve (whose tilt residuals are compressed, so its memory does not grow with the test);
# the per-sample Ceres baseline, a cross-check that holds every residual (56 s and 9.5 GB at
# 10^7), runs on the course data only. The check lines go to stderr;
# stdout is the table. Exit status 1 when any check disagrees.
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
source "$ACCELCAL_ROOT/tools/setup.sh"
accelcal_install_packages

build=${ACCELCAL_BUILD_DIR:-$ACCELCAL_ROOT/build}
data=${ACCELCAL_COURSE_DATA:-$ACCELCAL_ROOT/../shared/data/tp2-2018}
simulated_samples=${ACCELCAL_PEERS_SAMPLES:-10000000}
# Debian's numpy and SciPy live in the system interpreter; a python3 earlier on PATH may
# lack them.
python=/usr/bin/python3
peers_py=$ACCELCAL_ROOT/tools/bench/peers.py

say() { echo "peers: $*" >&2; }

if [ ! -d "$data" ]; then
  say "no course data at $data; set ACCELCAL_COURSE_DATA"
  exit 2
fi
if [ ! -f "$build/CMakeCache.txt" ]; then
  say "no build in $build; run ./tools/test.sh first (or set ACCELCAL_BUILD_DIR)"
  exit 2
fi
for target in peer_timing simulate; do
  if [ ! -x "$build/bin/$target" ]; then
    say "building $target in $build"
    if ! cmake --build "$build" --target "$target" -j "$(nproc 2>/dev/null || echo 2)" \
      >"$build/peers-build.log" 2>&1; then
      tail -30 "$build/peers-build.log" >&2
      say "building $target failed; the full log is $build/peers-build.log"
      exit 2
    fi
  fi
done

work=$(mktemp -d "${TMPDIR:-/tmp}/accelcal-peers.XXXXXX")
trap 'rm -rf "$work"' EXIT

status=0

# One data set: accelcal's timings and estimates first, then the peers', checked against them.
# $1 label, $2 data folder, then arguments shared by both sides, then '--' and peers.py's own;
# accelcal_only holds peer_timing's own.
compare() {
  local label=$1 dir=$2
  shift 2
  local shared=()
  while [ $# -gt 0 ] && [ "$1" != "--" ]; do
    shared+=("$1")
    shift
  done
  [ $# -gt 0 ] && shift
  say "$label: accelcal (peer_timing) on $dir"
  "$build/bin/peer_timing" --data_dir="$dir" "${shared[@]}" "${accelcal_only[@]}" --json="$work/$label-accelcal.json"
  say "$label: numpy/SciPy (peers.py)"
  "$python" "$peers_py" run --data_dir="$dir" "${shared[@]}" "$@" \
    --accelcal_json="$work/$label-accelcal.json" --json="$work/$label.json" >&2 || status=1
}

# The course data: many repetitions, since every solve takes milliseconds; both of the
# researcher's least_squares variants.
accelcal_only=()
compare course "$data" --repetitions=21 --time_budget=20

# The large test, simulated once from the course's scenario with only the tilt test's size
# changed. The peers' joint solve gives up after 4 minutes (and the table says so); its
# 2-point variant (7 residual evaluations per iteration over 2 x 10^7 rows) is left out.
say "simulating a tilt test of $simulated_samples samples"
"$build/bin/simulate" --out_dir="$work/simulated" --set=tilt_samples="$simulated_samples" >/dev/null
accelcal_only=(--problems=baseline_closed_form,joint)
compare simulated "$work/simulated" --repetitions=5 --time_budget=20 -- --jacobians=analytic \
  --joint_time_limit=240

"$python" "$peers_py" table course="$work/course.json" simulated="$work/simulated.json" || status=1
exit "$status"
