#!/usr/bin/env bash
# An installed prefix runs analyze on the course data without the source tree:
#
#   installed_analyze_test.sh BUILD_DIR SOURCE_DIR
#
# cmake --install into a scratch prefix, which is then moved (an installed tree must not depend
# on where it was installed); every binary and plot script is there; the installed analyze's
# default --tools_dir is the moved prefix's share/accelcal/tools; and analyze, run from a
# scratch folder on a copy of the course data, writes report.html, report.md, results.json and
# the three figures. Where a mount namespace is allowed (unshare), the source and build trees
# are hidden behind empty folders during that run, so a script read from the source tree's
# tools/ (the compiled-in fallback) would fail the test. Skips (77) without the course data or
# without matplotlib.
set -euo pipefail
build_dir=$(cd "$1" && pwd)
source_dir=$(cd "$2" && pwd)
data=${ACCELCAL_COURSE_DATA:-}
if [ -z "$data" ] || [ ! -f "$data/acel.mat" ]; then
  echo "SKIP: no course data (set ACCELCAL_COURSE_DATA)"
  exit 77
fi
python=/usr/bin/python3
if ! "$python" -c "import matplotlib, numpy" 2>/dev/null; then
  echo "SKIP: $python has no matplotlib/numpy"
  exit 77
fi
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

cmake --install "$build_dir" --prefix "$scratch/installed" >/dev/null
mv "$scratch/installed" "$scratch/prefix"
prefix=$scratch/prefix

for binary in analyze coverage discover joint linear_ls min_samples null_rate power simulate trajectory; do
  [ -x "$prefix/bin/$binary" ] || { echo "FAIL: $prefix/bin/$binary not installed"; exit 1; }
done
for script in plot_discovery.py plot_min_samples.py plot_trajectory.py; do
  [ -f "$prefix/share/accelcal/tools/$script" ] || { echo "FAIL: $script not installed"; exit 1; }
done
[ -f "$prefix/share/accelcal/scenarios/tp2-2018.json" ] || { echo "FAIL: scenarios not installed"; exit 1; }
[ -f "$prefix/include/accelcal/io/course_data.h" ] || { echo "FAIL: headers not under include/accelcal"; exit 1; }

# The default --tools_dir, as --help states it, is the moved prefix's, not the source tree's.
if ! "$prefix/bin/analyze" --help | grep -qF "default: \"$prefix/share/accelcal/tools\""; then
  echo "FAIL: the installed analyze's default --tools_dir is not $prefix/share/accelcal/tools:"
  "$prefix/bin/analyze" --help | grep -A1 tools_dir
  exit 1
fi

cp -r "$data" "$scratch/data"
# A sanitized build (./tools/test.sh --sanitize) reads LeakSanitizer's suppressions from the
# source tree, which the run below hides: a copy is read instead.
lsan_supp=$(sed -n 's/.*suppressions=\([^:]*\).*/\1/p' <<<"${LSAN_OPTIONS:-}")
if [ -n "$lsan_supp" ] && [ -f "$lsan_supp" ]; then
  cp "$lsan_supp" "$scratch/lsan.supp"
  export LSAN_OPTIONS=${LSAN_OPTIONS//$lsan_supp/$scratch/lsan.supp}
fi
mkdir "$scratch/work" "$scratch/empty"
run_analyze=(env -u ACCELCAL_TOOLS_DIR "$prefix/bin/analyze" --data_dir="$scratch/data"
  --out_dir="$scratch/report" --python="$python")
# In a private mount namespace: each folder before -- hidden behind an empty one (the build
# tree first: it usually lies inside the source tree), then the run.
# shellcheck disable=SC2016  # expanded by the inner shell
hide_and_run='empty=$1 work=$2; shift 2
while [ "$1" != -- ]; do
  mount --bind "$empty" "$1" || exit 3
  [ -z "$(ls -A "$1")" ] || { echo "FAIL: $1 is still visible"; exit 3; }
  shift
done
shift
cd "$work" && exec "$@"'
status=0
if unshare -m -r true 2>/dev/null; then
  echo "the source and build trees are hidden during the run (mount namespace)"
  unshare -m -r bash -c "$hide_and_run" hide "$scratch/empty" "$scratch/work" \
    "$build_dir" "$source_dir" -- "${run_analyze[@]}" >"$scratch/stdout" 2>&1 || status=$?
else
  echo "note: no mount namespace here (unshare -m -r refused); the source tree stays visible"
  (cd "$scratch/work" && "${run_analyze[@]}") >"$scratch/stdout" 2>&1 || status=$?
fi
cat "$scratch/stdout"
[ "$status" -eq 0 ] || { echo "FAIL: the installed analyze exited with $status"; exit 1; }
for file in report.html report.md results.json discovery.png trajectory.png min_samples.png; do
  [ -s "$scratch/report/$file" ] || { echo "FAIL: the report has no $file"; exit 1; }
done
if grep -q "Figures not drawn" "$scratch/report/report.md"; then
  echo "FAIL: the report says figures were not drawn:"
  grep -A3 "Figures not drawn" "$scratch/report/report.md"
  exit 1
fi
echo "PASS: the installed analyze wrote report.html, report.md, results.json and the three figures"
