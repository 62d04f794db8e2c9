#!/usr/bin/env bash
# accelcal beside imu_tk itself: imu_tk's own example (apps/test_imu_calib.cpp, accelerometer
# and gyroscope on its Xsens log), built here from imu_tk's BSD source, against calibrate_imu
# --mode=imu_tk with the gyroscope and against calibrate_imu --mode=ml, on the same files, in
# the same run. Each program is timed as a whole process (wall time, and the CPU time of the
# process from bash's `times`), N runs each, interleaved, after one untimed round. Prints the
# checks, a table of medians and ends with
#   ratio imu_tk/accelcal imu_tk_mode=X ml=Y
# (imu_tk's median wall time over calibrate_imu's, for each mode), after the same ratio of the
# median CPU times.
#
#   ACCELCAL_IMU_TK_SOURCE=PATH tools/bench/imu_tk_peer.sh [N]        # N: runs each, default 9
#
# ACCELCAL_IMU_TK_SOURCE (required): imu_tk's source, either a source tree (with
# apps/test_imu_calib.cpp) or a git directory (a bare mirror of github.com/iralabdisco/imu_tk or
# of a fork; its HEAD is read with git archive). imu_tk's code is never copied into this
# repository: it is built in ACCELCAL_IMU_TK_BUILD (default build/imu_tk-peer, untracked),
# once, and rebuilt only when the source, the patches or the compiler change.
# Other environment: ACCELCAL_IMU_TK_DATA (default ../shared/data/imu_tk-xsens),
# ACCELCAL_BUILD_DIR (default build/; calibrate_imu is built there if out of date).
#
# How imu_tk is built. Its CMakeLists.txt requires Qt4, OpenGL and GLUT (find_package(Qt4 ...
# REQUIRED)) for its plots and 3-D viewer; Debian 12 no longer ships Qt4. The example uses none
# of it except through the plots, so the script compiles imu_tk's three core translation units
# (src/calibration.cpp, src/filters.cpp, src/io_utils.cpp) and apps/test_imu_calib.cpp with g++
# directly, at imu_tk's CMake Release flags (-O3 -DNDEBUG; -std=gnu++17, g++ 12's default and
# what Ceres 2.1's headers need), against Debian's Ceres 2.1, Eigen 3.4 and glog, and links
# -lceres -lglog. Left out: src/visualization.cpp and src/vis_extra/ (gnuplot pipes, Qt/OpenGL).
# The example is compiled unchanged (it includes imu_tk/visualization.h, which needs Boost's
# headers: libboost-dev). Patched, on copies in the build directory, nothing else:
#   1. src/calibration.cpp, MultiPosCalibration_::calibrateAcc's verbose branch: the three lines
#      `Plot plot;`, `plot.plotIntervals( calib_acc_samples_, min_cost_static_intervals_);` and
#      `waitForKey();` are deleted: with verbose output on (the example turns it on, and it is
#      how the example prints its result) they open a gnuplot pipe to plot the accelerometer's
#      intervals and wait for Enter. The printed text around them is unchanged.
#   2. include/imu_tk/calibration.h: `_T setInitStaticIntervalDuration( _T duration )` becomes
#      `void ...`. It has no return statement, so calling it (the example does) is undefined
#      behaviour; g++ 12 at -O3 compiles the fall-off as unreachable and the example dies with
#      SIGSEGV before calibrating (Kyle-ak/imu_tk issue 7; the fix given there is this one).
#      setIntarvalsNumSamples and enableGyroBiasOptimization have the same defect but the
#      example does not call them; they are left as they are.
# The example runs as imu_tk ships it: g = 9.81744, 50 s initial rest, accelerometer offsets
# starting at 32768, gyroscope gains at 1/6258, acc_use_means false, the gyroscope's bias from
# the initial rest, its time step from the time stamps, verbose output (Ceres' per-iteration
# lines and the gyroscope's full report included), and test_imu_{acc,gyro}.calib written to the
# working directory. calibrate_imu gets the same settings and writes the same two files
# (--imu_tk_calib_out).
#
# Checks, every run: imu_tk's printed gyroscope result (residual, misalignment, scale, bias
# lines) is the text calibrate_imu prints as imu_tk's printout, and the digits quoted from
# imu_tk on this log; the gyroscope's Ceres solve has the same iterations, initial and final
# cost (Ceres' %e) in both; both programs' .calib files (accelerometer and gyroscope) are byte
# for byte the same; every run exits 0.
# --mode=ml is run with the gyroscope flags (--gyro_log, --initial_gyro_gain); a build whose
# mode ml refuses them (exit 2) is timed on the accelerometer alone and the table says so.
#
# Exit status: 0 when every check passes; 1 when an output disagrees; 2 when the source, the
# data or a build is missing or fails, or a program fails.
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)

say() { echo "imu_tk_peer: $*" >&2; }

# The source first, in one line, before anything is installed or built.
source "$ACCELCAL_ROOT/tools/bench/imu_tk_build.sh"
imu_tk_check_source

runs=${1:-9}
if ! [[ $runs =~ ^[1-9][0-9]*$ ]]; then
  say "N must be a positive number of runs (got '$runs')"
  exit 2
fi
build=${ACCELCAL_BUILD_DIR:-$ACCELCAL_ROOT/build}
cache=${ACCELCAL_IMU_TK_BUILD:-$build/imu_tk-peer}
data=${ACCELCAL_IMU_TK_DATA:-$ACCELCAL_ROOT/../shared/data/imu_tk-xsens}
acc=$data/xsens_acc.mat
gyro=$data/xsens_gyro.mat
for f in "$acc" "$gyro"; do
  if [ ! -f "$f" ]; then
    say "no $f; set ACCELCAL_IMU_TK_DATA to the imu_tk-xsens folder"
    exit 2
  fi
done
acc=$(cd "$data" && pwd)/xsens_acc.mat
gyro=$(cd "$data" && pwd)/xsens_gyro.mat

source "$ACCELCAL_ROOT/tools/setup.sh"
# libboost-dev: the example includes imu_tk/visualization.h (boost/shared_ptr.hpp).
accelcal_install_packages libboost-dev || exit 2
accelcal_build "$build" --target calibrate_imu || exit 2
calibrate_imu=$build/bin/calibrate_imu

imu_tk_build "$cache"

# ---- The runs ---------------------------------------------------------------------------------
work=$(mktemp -d "${TMPDIR:-/tmp}/accelcal-imu_tk-peer.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/imu_tk" "$work/accelcal" "$work/ml"

common=(--log="$acc" --g=9.81744 --init_rest_s=50)
# 1/6258 to 17 digits, imu_tk's start. (0.000159795, the 6 digits calibrate_imu's --help quotes,
# starts the gyroscope's solve at a cost of 8.53101 instead of imu_tk's 8.530865; the printed
# result is the same.)
gyro_flags=(--gyro_log="$gyro" --initial_gyro_gain=0.00015979546180888463)
# The three commands; run_timed and check read them through namerefs (cmd_NAME).
# shellcheck disable=SC2034
cmd_imu_tk=("$imu_tk_bin" "$acc" "$gyro")
# shellcheck disable=SC2034
cmd_accelcal=("$calibrate_imu" "${common[@]}" "${gyro_flags[@]}" --mode=imu_tk
  --initial_offset=32768 --imu_tk_calib_out="$work/accelcal/test_imu")
# shellcheck disable=SC2034
cmd_ml=("$calibrate_imu" "${common[@]}" "${gyro_flags[@]}" --mode=ml)

# The lines imu_tk prints for the gyroscope on this log (quoted in the issues that use it).
published='Gyroscopes calibration: residual 0.00150696
Misalignment Matrix
         1 0.00593634 0.00111101
0.00808812          1 -0.0535569
 0.0253067 -0.0025513          1
Scale Matrix
0.000209295           0           0
          0 0.000209899           0
          0           0 0.000209483
Bias Vector
32777.1
32459.8
32511.8'

# run_timed NAME: runs cmd_NAME in $work/NAME (stdout, stderr to files there) and sets rc, wall
# and cpu (seconds). No command substitution or pipe between the two `times`: a forked
# subshell's CPU time would be counted.
run_timed() {
  local name=$1
  local -n cmd="cmd_$name"
  rm -f "$work/$name"/*.calib # a run that writes none must not pass on the last run's
  cd "$work/$name"
  times >"$work/times0"
  local t0=$EPOCHREALTIME
  rc=0
  "${cmd[@]}" >"$work/$name/stdout" 2>"$work/$name/stderr" </dev/null || rc=$?
  local t1=$EPOCHREALTIME
  times >"$work/times1"
  cd "$ACCELCAL_ROOT"
  wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.6f", b - a }')
  cpu=$(awk 'function s(x) { sub(/s$/, "", x); split(x, p, "m"); return p[1] * 60 + p[2] }
    FNR == 2 { c[FILENAME] = s($1) + s($2) } END { printf "%.3f", c[ARGV[2]] - c[ARGV[1]] }' \
    "$work/times0" "$work/times1")
}

# The gyroscope block of imu_tk's stdout / of calibrate_imu's printout of imu_tk's text.
imu_tk_block() { awk '/^Gyroscopes calibration: residual/ { p = 1 } p && /^$/ { exit } p' "$1"; }
accelcal_block() {
  awk '/^  Gyroscopes calibration: residual/ { p = 1 } p && /^$/ { exit } p' "$1" | sed 's/^  //'
}
# The gyroscope's solve as Ceres reports it: iterations, initial cost, final cost (imu_tk prints
# Ceres' full report for the gyroscope only; calibrate_imu a one-line report per solve, the
# gyroscope's last).
imu_tk_solve() {
  awk '/^Initial / { i = $2 } /^Final / { f = $2 } /^Minimizer iterations/ { n = $3 }
    END { print n, i, f }' "$1"
}
accelcal_solve() {
  grep '^Ceres Solver Report' "$1" | tail -1 |
    sed -E 's/.*Iterations: ([0-9]+), Initial cost: ([^,]+), Final cost: ([^,]+),.*/\1 \2 \3/'
}

failures=0
fail() {
  say "FAIL: $*"
  failures=$((failures + 1))
}

# check NAME: the outputs of the run just made.
check() {
  local name=$1
  local -n run_cmd="cmd_$name"
  if [ "$rc" != 0 ]; then
    head -5 "$work/$name/stderr" >&2
    say "$name exited with status $rc; its command: ${run_cmd[*]}"
    exit 2
  fi
  case $name in
    imu_tk)
      [ "$(imu_tk_block "$work/imu_tk/stdout")" = "$published" ] ||
        fail "imu_tk's gyroscope lines differ from the published ones: $(imu_tk_block "$work/imu_tk/stdout" | tr '\n' '|')"
      [ "$(imu_tk_block "$work/imu_tk/stdout")" = "$reference_block" ] ||
        fail "imu_tk's gyroscope lines differ from calibrate_imu's printout of them"
      [ "$(imu_tk_solve "$work/imu_tk/stdout")" = "$reference_solve" ] ||
        fail "the gyroscope's solve (iterations, initial and final cost): imu_tk $(imu_tk_solve "$work/imu_tk/stdout"), calibrate_imu $reference_solve"
      for s in acc gyro; do
        cmp -s "$work/imu_tk/test_imu_$s.calib" "$work/reference_$s.calib" ||
          fail "imu_tk's test_imu_$s.calib differs from calibrate_imu's"
      done
      ;;
    accelcal)
      [ "$(accelcal_block "$work/accelcal/stdout")" = "$reference_block" ] ||
        fail "calibrate_imu's printout of imu_tk's gyroscope lines changed between runs"
      for s in acc gyro; do
        cmp -s "$work/accelcal/test_imu_$s.calib" "$work/reference_$s.calib" ||
          fail "calibrate_imu's test_imu_$s.calib changed between runs"
      done
      ;;
  esac
}

echo "imu_tk beside calibrate_imu: $acc, $gyro"
echo "imu_tk: test_imu_calib from $imu_tk_id, g++ $("$cxx" -dumpfullversion) ${cxxflags[*]}, two patches (this script's header), in $cache"
echo "accelcal: $calibrate_imu ($(git -C "$ACCELCAL_ROOT" rev-parse --short HEAD)$(git -C "$ACCELCAL_ROOT" diff --quiet HEAD -- src problems 2>/dev/null || echo ', modified'))"
echo "machine: $(nproc) cores; load before: $(uptime | sed 's/.*load average/load average/')"

# The untimed round: outputs for the checks, and mode ml's answer to the gyroscope flags.
ml_label="ml (accelerometer and gyroscope)"
run_timed accelcal
[ "$rc" = 0 ] || check accelcal # exits
reference_block=$(accelcal_block "$work/accelcal/stdout")
reference_solve=$(accelcal_solve "$work/accelcal/stdout")
cp "$work/accelcal/test_imu_acc.calib" "$work/reference_acc.calib"
cp "$work/accelcal/test_imu_gyro.calib" "$work/reference_gyro.calib"
if [ "$reference_block" != "$published" ]; then
  fail "calibrate_imu's printout of imu_tk's gyroscope lines differs from the published ones: $(echo "$reference_block" | tr '\n' '|')"
fi
run_timed imu_tk
check imu_tk
run_timed ml
if [ "$rc" = 2 ]; then
  say "mode ml refused the gyroscope flags: $(head -1 "$work/ml/stderr")"
  # shellcheck disable=SC2034
  cmd_ml=("$calibrate_imu" "${common[@]}" --mode=ml)
  ml_label="ml (accelerometer only: this build's ml refuses the gyroscope)"
  run_timed ml
fi
check ml
if [ "$failures" -eq 0 ]; then
  say "check: imu_tk's gyroscope lines = calibrate_imu's printout of them = the published digits;" \
    "the gyroscope's solve the same in both (iterations, initial cost, final cost: $reference_solve);" \
    "test_imu_acc.calib and test_imu_gyro.calib byte for byte the same"
fi

# N timed rounds, each in a different order of the three.
names=(imu_tk accelcal ml)
declare -A walls cpus
for ((i = 0; i < runs; i++)); do
  for ((j = 0; j < 3; j++)); do
    name=${names[$(((i + j) % 3))]}
    run_timed "$name"
    check "$name"
    walls[$name]+="$wall "
    cpus[$name]+="$cpu "
  done
done
echo "load after: $(uptime | sed 's/.*load average/load average/')"

# median VALUES...: the middle one, the mean of the two middle ones for an even count.
median() {
  printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END {
    if (NR % 2) printf "%.6f", v[(NR + 1) / 2]; else printf "%.6f", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
declare -A med_wall med_cpu
printf '\n%11s %9s %9s %10s %4s  %s\n' "wall median" min max "CPU median" runs \
  "program (whole process, interleaved)"
for name in imu_tk accelcal ml; do
  read -r -a w <<<"${walls[$name]}"
  read -r -a c <<<"${cpus[$name]}"
  med_wall[$name]=$(median "${w[@]}")
  med_cpu[$name]=$(median "${c[@]}")
  case $name in
    imu_tk) label="imu_tk test_imu_calib (accelerometer and gyroscope)" ;;
    accelcal) label="accelcal calibrate_imu --mode=imu_tk (accelerometer and gyroscope)" ;;
    ml) label="accelcal calibrate_imu --mode=$ml_label" ;;
  esac
  printf '%8.1f ms %6.1f ms %6.1f ms %7.1f ms %4d  %s\n' \
    "$(awk -v x="${med_wall[$name]}" 'BEGIN { print x * 1000 }')" \
    "$(printf '%s\n' "${w[@]}" | sort -g | head -1 | awk '{ print $1 * 1000 }')" \
    "$(printf '%s\n' "${w[@]}" | sort -g | tail -1 | awk '{ print $1 * 1000 }')" \
    "$(awk -v x="${med_cpu[$name]}" 'BEGIN { print x * 1000 }')" "${#w[@]}" "$label"
done
for name in imu_tk accelcal ml; do
  read -r -a w <<<"${walls[$name]}"
  say "$name wall (s): ${w[*]}"
done
if [ "$failures" -gt 0 ]; then
  say "$failures checks failed (FAIL lines above)"
  exit 1
fi
# CPU time first: on a shared machine it moves less than wall time. The wall ratio last.
awk -v i="${med_cpu[imu_tk]}" -v a="${med_cpu[accelcal]}" -v m="${med_cpu[ml]}" \
  'BEGIN { printf "CPU ratio imu_tk/accelcal imu_tk_mode=%.2f ml=%.2f\n", i / a, i / m }'
awk -v i="${med_wall[imu_tk]}" -v a="${med_wall[accelcal]}" -v m="${med_wall[ml]}" \
  'BEGIN { printf "ratio imu_tk/accelcal imu_tk_mode=%.2f ml=%.2f\n", i / a, i / m }'
