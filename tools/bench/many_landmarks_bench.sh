#!/usr/bin/env bash
# Many landmarks (issue 15: "2,001 landmarks take 30-40 s in joint, min_samples, discover;
# 100,000 landmarks take 69 s"): the course data with 2,001 landmarks in puntos.mat, all
# within about 60 m of the endpoint (every one plausible, none coincident), and a CSV of
# 100,000 landmarks; wall time and peak memory of each binary, median of three runs.
#   tools/bench/many_landmarks_bench.sh [DATA_DIR]     (ACCELCAL_BENCH_BIN=DIR: other binaries)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
data=${1:-$root/../shared/data/tp2-2018}
bin=${ACCELCAL_BENCH_BIN:-$root/build/bin}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r "$data" "$work/course2k"
chmod -R u+w "$work/course2k"
/usr/bin/python3 - "$work" <<'PY'
import sys, numpy as np, scipy.io
work = sys.argv[1]
rng = np.random.default_rng(2)
points = {"L%d" % k: np.array([[rng.uniform(400, 520), rng.uniform(0, 120)]]) for k in range(2001)}
scipy.io.savemat(work + "/course2k/puntos.mat", points)
with open(work + "/landmarks100k.csv", "w") as f:
    f.write("name,x,y\n")
    for k in range(100000):
        f.write("L%d,%.3f,%.3f\n" % (k, rng.uniform(-5000, 5000), rng.uniform(-5000, 5000)))
PY
measure() {
  local label=$1
  shift
  local times=()
  local memory=0
  for run in 1 2 3; do
    /usr/bin/time -f "%e %M" -o "$work/time" "$@" >/dev/null 2>"$work/stderr" ||
      { echo "$label failed: $(cat "$work/stderr")" >&2; return 1; }
    read -r seconds kilobytes <"$work/time"
    times+=("$seconds")
    memory=$kilobytes
  done
  median=$(printf '%s\n' "${times[@]}" | sort -n | sed -n 2p)
  printf '  %-58s %8s s %8d MiB\n' "$label" "$median" $((memory / 1024))
}
echo "many landmarks: median wall time of 3 runs, peak RSS"
measure "trajectory, 100,000 landmarks (CSV)" \
  "$bin/trajectory" --data_dir="$data" --landmarks_file="$work/landmarks100k.csv"
measure "trajectory, 2,001 landmarks (puntos.mat)" "$bin/trajectory" --data_dir="$work/course2k"
measure "joint --effects=angle_offset --landmark=auto, 2,001" \
  "$bin/joint" --data_dir="$work/course2k" --effects=angle_offset
measure "discover, 2,001" "$bin/discover" --data_dir="$work/course2k"
measure "min_samples --repetitions=0, 2,001" \
  "$bin/min_samples" --data_dir="$work/course2k" --repetitions=0
