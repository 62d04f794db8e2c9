#!/usr/bin/env bash
# Kills a binary (kill -9) at several moments while it writes a large output and checks that
# what is left is either the old output or the new one whole, never a part:
#
#   kill_mid_write_test.sh BIN_DIR
#
# simulate writes a 40-MB CSV folder (file by file through temporary files, then the folder
# renamed into place); a second round replaces an existing folder with --overwrite. At least
# one kill must land while the temporary folder exists, or the test proves nothing and fails.
set -uo pipefail
bin_dir=$1
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# A folder is whole when all five files are there and the data load and fit.
whole() {
  local dir=$1
  for file in calibration.csv trajectory.csv landmarks.csv scenario.json truth.json; do
    [ -f "$dir/$file" ] || return 1
  done
  "$bin_dir/linear_ls" --data_dir="$dir" --json="$scratch/check.json" >/dev/null 2>&1
}

big="--format=csv --set=tilt_samples=600000"
mid_write=0
for round in fresh overwrite; do
  out="$scratch/$round"
  if [ $round = overwrite ]; then
    "$bin_dir/simulate" --out_dir="$out" --set=tilt_samples=100 --format=csv >/dev/null ||
      fail "could not write the old folder"
    old_truth=$(cat "$out/truth.json")
  fi
  for delay in 0.05 0.15 0.3 0.5 0.8 1.5; do
    "$bin_dir/simulate" --out_dir="$out" $big --seed=7 --overwrite >/dev/null 2>&1 &
    pid=$!
    sleep $delay
    kill -9 $pid 2>/dev/null
    wait $pid 2>/dev/null
    temporaries=$(ls -d "$out".tmp.* 2>/dev/null | wc -l)
    if [ "$temporaries" -gt 0 ]; then
      mid_write=$((mid_write + 1))
      rm -rf "$out".tmp.*
    fi
    if [ -e "$out" ]; then
      whole "$out" || fail "$round, killed after ${delay}s: $out is a partial folder"
      if [ $round = overwrite ] && [ "$(cat "$out/truth.json")" != "$old_truth" ]; then
        old_truth=$(cat "$out/truth.json")  # the new folder landed whole
      fi
    elif [ $round = overwrite ]; then
      fail "overwrite, killed after ${delay}s: the old folder is gone and no new one replaced it"
    fi
    echo "$round: killed after ${delay}s: $([ "$temporaries" -gt 0 ] && echo mid-write || echo before or after writing); output $([ -e "$out" ] && echo whole || echo absent)"
  done
done
[ $mid_write -gt 0 ] || fail "no kill landed while the output was being written"
echo "PASS: $mid_write kills landed mid-write; every output left was whole"
