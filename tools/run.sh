#!/usr/bin/env bash
# The README's first command: install what is missing, build in Release, run the main job.
# The main job is `analyze`: every stage on the embedded default (the course's setting
# simulated with an angle offset hidden in it), written to report/ (replaced each run).
# Extra arguments go to analyze, e.g. ./tools/run.sh --data_dir=../shared/data/tp2-2018
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ACCELCAL_ROOT/tools/setup.sh"
accelcal_install_packages
# Only analyze and what it links: the tests, benchmarks and fuzz replays are tools/test.sh's.
accelcal_build "$ACCELCAL_ROOT/build" --target analyze
# The Python module, registered for /usr/bin/python3 (docs/python.md).
accelcal_build_python "$ACCELCAL_ROOT/build"
exec "$ACCELCAL_ROOT/build/bin/analyze" --out_dir="$ACCELCAL_ROOT/report" --overwrite "$@"
