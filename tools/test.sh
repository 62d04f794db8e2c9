#!/usr/bin/env bash
# The README's second command: install what is missing, build in Release, run every test.
#
#   ./tools/test.sh [ctest args...]             build/ (g++, Release)
#   ./tools/test.sh --sanitize [ctest args...]  build-sanitize/ (clang, RelWithDebInfo): every
#                                               target with AddressSanitizer and UBSan, the
#                                               fuzz targets replaying their seeds
#
# Tests that need the course data read it from $ACCELCAL_COURSE_DATA
# (default ../shared/data/tp2-2018, relative to the repository) and skip visibly without it.
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ACCELCAL_ROOT/tools/setup.sh"
build_dir="$ACCELCAL_ROOT/build"
if [ "${1:-}" = "--sanitize" ]; then
  shift
  accelcal_install_packages "${ACCELCAL_SANITIZE_PACKAGES[@]}"
  build_dir="$ACCELCAL_ROOT/build-sanitize"
  accelcal_build "$build_dir" "${ACCELCAL_SANITIZE_CMAKE_ARGS[@]}"
  # halt_on_error: the first report fails the test. Leaks are checked (LeakSanitizer);
  # tests/sanitizer/lsan.supp lists the libraries' own process-lifetime allocations.
  export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1:strict_string_checks=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
  export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$ACCELCAL_ROOT/tests/sanitizer/lsan.supp}
  # The statistical tests of ACCELCAL_SANITIZE_SKIPPED (tools/setup.sh) repeat, hundreds or
  # thousands of times, code that the other tests run once; instrumented, they would take
  # most of the suite's time and find nothing the others do not. The plain suite runs them;
  # ACCELCAL_SANITIZE_ALL=1 runs them here too.
  if [ "${ACCELCAL_SANITIZE_ALL:-0}" != 1 ]; then
    set -- -E "$ACCELCAL_SANITIZE_SKIPPED" "$@"
  fi
else
  accelcal_install_packages
  accelcal_build "$build_dir"
fi
export ACCELCAL_COURSE_DATA=${ACCELCAL_COURSE_DATA:-$ACCELCAL_ROOT/../shared/data/tp2-2018}
cd "$build_dir"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
