#!/usr/bin/env bash
# cmake --install into a scratch prefix, then configure, build and run a project outside the
# tree that uses find_package(accelcal).
set -euo pipefail
build_dir=$1
source_dir=$2
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cmake --install "$build_dir" --prefix "$scratch/prefix" >/dev/null
# Every binary problems/ builds is installed (the README's commands run from an installed prefix).
missing=""
for binary in $(sed -n 's/^add_executable(\([a-z_]*\) .*/\1/p' "$source_dir/problems/CMakeLists.txt"); do
  [ -x "$scratch/prefix/bin/$binary" ] || missing="$missing $binary"
done
if [ -n "$missing" ]; then
  echo "install_test: not installed:$missing" >&2
  exit 1
fi
# The consumer is built with the compiler the library was (a sanitized build uses clang).
compiler=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build_dir/CMakeCache.txt")
cmake -S "$source_dir/tests/consumer" -B "$scratch/build" -DCMAKE_PREFIX_PATH="$scratch/prefix" \
  -DCMAKE_BUILD_TYPE=Release ${compiler:+-DCMAKE_CXX_COMPILER="$compiler"} >/dev/null
cmake --build "$scratch/build" >/dev/null
output=$("$scratch/build/consumer")
echo "$output"
[[ "$output" == bias_x* ]]
