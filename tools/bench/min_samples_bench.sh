#!/usr/bin/env bash
# The whole how-many-samples analysis on the course data, with the default Monte Carlo
# (1000 repetitions per checked N, 4 designs, 2 threads): wall time of three runs.
#   tools/bench/min_samples_bench.sh [DATA_DIR]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
data=${1:-$root/../shared/data/tp2-2018}
for run in 1 2 3; do
  start=$(date +%s%N)
  "$root/build/bin/min_samples" --data_dir="$data" --design=all >/dev/null
  end=$(date +%s%N)
  elapsed_ms=$(((end - start) / 1000000))
  printf 'run %d: %d.%03d s\n' "$run" $((elapsed_ms / 1000)) $((elapsed_ms % 1000))
done
