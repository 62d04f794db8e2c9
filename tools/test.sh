#!/usr/bin/env bash
# The README's second command: install what is missing, build in Release, run every test.
#
#   ./tools/test.sh [ctest args...]             build/ (g++, Release)
#   ./tools/test.sh --sanitize [ctest args...]  build-sanitize/ (clang, -O1, line tables):
#                                               every target with AddressSanitizer and UBSan;
#                                               the unit tests, the bad-input corpora and the
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
  end_to_end=OFF
  [ "${ACCELCAL_SANITIZE_ALL:-0}" = 1 ] && end_to_end=ON
  accelcal_build "$build_dir" "${ACCELCAL_SANITIZE_CMAKE_ARGS[@]}" \
    -DACCELCAL_BUILD_END_TO_END_TESTS=$end_to_end
  # halt_on_error: the first report fails the test. Leaks are checked (LeakSanitizer);
  # tests/sanitizer/lsan.supp lists the libraries' own process-lifetime allocations.
  export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1:strict_string_checks=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
  export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$ACCELCAL_ROOT/tests/sanitizer/lsan.supp}
  # What runs instrumented: the library's unit tests (label unit) and the bad-input and
  # bad-flag corpora, which drive every binary's readers and flag checks with damaged input
  # (the fuzzers, tools/fuzz.sh, go further). Not here: the end-to-end tests (label
  # end_to_end: the binaries on good data, Python tools, installs, signals), which run code
  # the unit tests already run, at 4-5 times the plain suite's cost under ASan, and the
  # statistical tests of ACCELCAL_SANITIZE_SKIPPED (tools/setup.sh), which repeat it
  # hundreds or thousands of times. The plain suite runs them all; ACCELCAL_SANITIZE_ALL=1
  # runs them here too.
  if [ "${ACCELCAL_SANITIZE_ALL:-0}" != 1 ]; then
    set -- -LE end_to_end -E "$ACCELCAL_SANITIZE_SKIPPED" "$@"
  fi
else
  accelcal_install_packages
  accelcal_build "$build_dir"
  accelcal_register_python "$build_dir"
fi
export ACCELCAL_COURSE_DATA=${ACCELCAL_COURSE_DATA:-$ACCELCAL_ROOT/../shared/data/tp2-2018}
cd "$build_dir"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
