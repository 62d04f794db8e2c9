#!/usr/bin/env bash
# The README's first command: install what is missing, build in Release, run the main job.
# Until the analysis issue lands, the main job is linear_ls on its embedded default
# (a synthetic tilt test simulated in-process with a fixed seed). Extra arguments are
# passed to the binary, e.g. ./tools/run.sh --data_dir=../shared/data/tp2-2018
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ACCELCAL_ROOT/tools/setup.sh"
accelcal_install_packages
accelcal_build "$ACCELCAL_ROOT/build"
exec "$ACCELCAL_ROOT/build/bin/linear_ls" "$@"
