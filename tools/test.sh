#!/usr/bin/env bash
# The README's second command: install what is missing, build in Release, run every test.
# Tests that need the course data read it from $ACCELCAL_COURSE_DATA
# (default ../shared/data/tp2-2018, relative to the repository) and skip visibly without it.
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ACCELCAL_ROOT/tools/setup.sh"
accelcal_install_packages
accelcal_build "$ACCELCAL_ROOT/build"
export ACCELCAL_COURSE_DATA=${ACCELCAL_COURSE_DATA:-$ACCELCAL_ROOT/../shared/data/tp2-2018}
cd "$ACCELCAL_ROOT/build"
ctest --output-on-failure -j "$(nproc 2>/dev/null || echo 2)" "$@"
