#!/usr/bin/env bash
# Fuzzes the readers users feed files to (CSV, datos.txt, .mat, IMU logs, calibration files, ROS 2
# bags' Imu messages) with libFuzzer under AddressSanitizer and UBSan, each for SECONDS (default
# 30), from the seeds of tests/fuzz/seeds and the bad-input corpus tests/data/bad:
#
#   ./tools/fuzz.sh [SECONDS] [TARGET[/SET]...]
#   targets: csv datos_txt mat_file imu_log calibration_file ros2_imu_message (default: all)
#
# TARGET/SET fuzzes one path of a target from one seed set alone, tests/fuzz/seeds/TARGET/SET
# (the bad-input corpus left out): mat_file/compressed (zlib streams), mat_file/v73 (HDF5).
# A plain TARGET starts from all its seeds, subfolders included, and the bad-input corpus.
#
# Builds the fuzz targets in build-sanitize/ with the flags ./tools/test.sh --sanitize uses
# (ACCELCAL_FUZZ_BUILD_DIR=DIR builds elsewhere). The growing corpus stays in
# <build>/fuzz/corpus/<target> (<target>_<set>) between runs; a crash is written to
# <build>/fuzz/findings/<target>/ and fails the script. Copy it to tests/fuzz/regressions/
# (named after what it found), fix the reader, and ctest replays it from then on.
#
# Memory: one allocation may not exceed 1 GB, nor the process 4 GB. A 64 KB input can hold a
# zlib stream that legitimately inflates to 66 MB of int8 values, which matio returns as
# 528 MB of doubles, copied once more by the loader; anything beyond that is a finding.
#
# ACCELCAL_FUZZ_SEED=N fixes libFuzzer's random seed (default: a new one each run), so that a
# run from an empty corpus can be repeated: CI fuzzes with seed 1 from a clean clone, and
#   rm -rf build-sanitize/fuzz/corpus && ACCELCAL_FUZZ_SEED=1 ./tools/fuzz.sh 600
# goes over the same first inputs and further.
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ACCELCAL_ROOT/tools/setup.sh"
seconds=${1:-30}
shift || true
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(csv datos_txt mat_file imu_log calibration_file ros2_imu_message)
if [ -n "${ACCELCAL_FUZZ_SEED:-}" ] && ! [[ $ACCELCAL_FUZZ_SEED =~ ^[1-9][0-9]*$ ]]; then
  echo "fuzz.sh: ACCELCAL_FUZZ_SEED must be a positive integer, got '$ACCELCAL_FUZZ_SEED'" >&2
  exit 2
fi
if ! [[ $seconds =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "fuzz.sh: SECONDS must be a positive integer, got '$seconds'" >&2
  exit 2
fi
for spec in "${targets[@]}"; do
  if ! [[ $spec =~ ^(csv|datos_txt|mat_file|imu_log|calibration_file|ros2_imu_message)(/[A-Za-z0-9_]+)?$ ]] ||
      { [[ $spec == */* ]] && [ ! -d "$ACCELCAL_ROOT/tests/fuzz/seeds/$spec" ]; }; then
    echo "fuzz.sh: no fuzz target or seed set '$spec' (targets: csv datos_txt mat_file imu_log calibration_file ros2_imu_message;" \
      "seed sets: the folders under tests/fuzz/seeds/TARGET/)" >&2
    exit 2
  fi
done
accelcal_install_packages "${ACCELCAL_SANITIZE_PACKAGES[@]}"
build_dir=${ACCELCAL_FUZZ_BUILD_DIR:-$ACCELCAL_ROOT/build-sanitize}
# Only the fuzz targets (and the library they link), not the whole instrumented suite.
fuzzers=()
for spec in "${targets[@]}"; do fuzzers+=("${spec%%/*}_fuzzer"); done
cmake -S "$ACCELCAL_ROOT" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "${ACCELCAL_SANITIZE_CMAKE_ARGS[@]}" \
  >/dev/null || { echo "fuzz.sh: cmake configure failed (run cmake -S . -B $build_dir)" >&2; exit 1; }
echo "fuzz.sh: building ${fuzzers[*]} in $build_dir (log: $build_dir/build.log)" >&2
if ! cmake --build "$build_dir" -j "$(nproc 2>/dev/null || echo 2)" --target "${fuzzers[@]}" \
    >"$build_dir/build.log" 2>&1; then
  grep -E -B2 -A6 'error|Error' "$build_dir/build.log" | head -80 >&2
  echo "fuzz.sh: build failed; the full log is $build_dir/build.log" >&2
  exit 1
fi
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$ACCELCAL_ROOT/tests/sanitizer/lsan.supp}

status=0
for spec in "${targets[@]}"; do
  target=${spec%%/*}
  name=${spec//\//_}  # mat_file/v73 -> mat_file_v73
  fuzzer="$build_dir/fuzz/${target}_fuzzer"
  [ -x "$fuzzer" ] || { echo "fuzz.sh: no fuzz target '$target' ($fuzzer)" >&2; exit 2; }
  corpus="$build_dir/fuzz/corpus/$name"
  findings="$build_dir/fuzz/findings/$name"
  mkdir -p "$corpus" "$findings"
  log="$build_dir/fuzz/$name.log"
  echo "fuzz.sh: $spec for ${seconds}s (log: $log)" >&2
  # New inputs go to the first corpus folder; the seeds and the bad corpus are read only.
  inputs=("$ACCELCAL_ROOT/tests/fuzz/seeds/$spec")
  [ "$spec" = "$target" ] && inputs+=("$ACCELCAL_ROOT/tests/data/bad")
  seed_flag=()
  [ -n "${ACCELCAL_FUZZ_SEED:-}" ] && seed_flag=(-seed="$ACCELCAL_FUZZ_SEED")
  if "$fuzzer" "${seed_flag[@]}" -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=4096 -malloc_limit_mb=1024 \
      -print_final_stats=1 -artifact_prefix="$findings/" "$corpus" "${inputs[@]}" >"$log" 2>&1; then
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
    cov=$(grep -Eo 'cov: [0-9]+' "$log" | tail -1)
    echo "fuzz.sh: $spec: ${runs:-?} inputs in ${seconds}s (${speed:-?}/s), $cov, corpus $(ls "$corpus" | wc -l) files, no finding" >&2
  else
    echo "fuzz.sh: $spec: FINDING (see $log and $findings):" >&2
    grep -E "ERROR|SUMMARY|deadly signal|Test unit written" "$log" | head -5 >&2
    status=1
  fi
done
exit $status
