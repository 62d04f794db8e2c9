#!/usr/bin/env bash
# cmake --install on a build where the installed targets are not built: it must fail, name them
# and the command that builds them, and copy nothing. The build is a scratch configure of the
# same source tree (nothing built in it), so the suite's own build/bin is left alone.
set -euo pipefail
build_dir=$1
source_dir=$2
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
compiler=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build_dir/CMakeCache.txt")
cmake -S "$source_dir" -B "$scratch/build" -DCMAKE_BUILD_TYPE=Release -DACCELCAL_BUILD_TESTS=OFF \
  -DACCELCAL_BUILD_BENCHMARKS=OFF -DACCELCAL_PYTHON=OFF \
  ${compiler:+-DCMAKE_CXX_COMPILER="$compiler"} >/dev/null
# Built: one of them (a stand-in file at its path), so that the message names only the others.
mkdir -p "$scratch/build/bin"
printf '#!/bin/sh\n' >"$scratch/build/bin/analyze"
chmod +x "$scratch/build/bin/analyze"
status=0
cmake --install "$scratch/build" --prefix "$scratch/prefix" >"$scratch/out" 2>&1 || status=$?
cat "$scratch/out"
if [ "$status" -eq 0 ]; then
  echo "install_refuses_test: cmake --install succeeded with nothing built" >&2
  exit 1
fi
for expected in "nothing installed" "not built: " " calibrate_imu" " allan" " accelcal_base" \
  "cmake --build $scratch/build --target"; do
  grep -qF -- "$expected" "$scratch/out" ||
    { echo "install_refuses_test: the message lacks '$expected'" >&2; exit 1; }
done
if grep -q "not built:.* analyze[ ;]" "$scratch/out"; then
  echo "install_refuses_test: analyze is built but named as not built" >&2
  exit 1
fi
if [ -e "$scratch/prefix" ] && [ -n "$(find "$scratch/prefix" -mindepth 1 -print -quit)" ]; then
  echo "install_refuses_test: copied before refusing:" >&2
  find "$scratch/prefix" >&2
  exit 1
fi
