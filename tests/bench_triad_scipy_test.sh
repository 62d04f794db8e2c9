#!/usr/bin/env bash
# The triad benchmark's peer stays a peer: on the first 250 s of imu_tk's Xsens log (18
# poses), tools/bench/triad_scipy.py must reproduce what accelcal computes (every imu_tk cost
# per k to 1e-6, the intervals, the parameters, the maximum-likelihood fit and its sigma;
# the checks of triad_scipy.py), so that tools/bench/triad_bench.sh times the same
# computation on both sides. Nothing is timed here (one repetition each, no ratio asked).
# Skips (exit 77) without numpy/SciPy or the data.
set -euo pipefail
bin_dir=$1
source_dir=$2
data=${ACCELCAL_IMU_TK_DATA:-$source_dir/../shared/data/imu_tk-xsens}
/usr/bin/python3 -c "import numpy, scipy" 2>/dev/null || { echo "SKIP: no python3-scipy"; exit 77; }
[ -f "$data/xsens_acc.mat" ] || { echo "SKIP: no imu_tk data at $data"; exit 77; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
head -n 25000 "$data/xsens_acc.mat" >"$scratch/short_acc.mat"
configuration=(--g=9.81744 --init_rest_s=50 --initial_offset=32768)
"$bin_dir/triad_bench" --log="$scratch/short_acc.mat" "${configuration[@]}" --repetitions=1 \
  --json="$scratch/accelcal.json"
/usr/bin/python3 "$source_dir/tools/bench/triad_scipy.py" --log="$scratch/short_acc.mat" \
  "${configuration[@]}" --repetitions=1 --accelcal_json="$scratch/accelcal.json" \
  >"$scratch/checks.txt" || { cat "$scratch/checks.txt"; exit 1; }
cat "$scratch/checks.txt"
# Every check ran and passed: configuration, samples, 9 k, chosen k, intervals, 9 + 9
# parameters, chi2, noise, 2 Jacobians.
passed=$(grep -c '^  PASS' "$scratch/checks.txt")
[ "$passed" -eq 35 ] || { echo "expected 35 PASS lines, got $passed"; exit 1; }
