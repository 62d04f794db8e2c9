#!/usr/bin/env bash
# calibrate_imu --mode=ml at scale (issue 36): synthetic hand-held logs of 10^5 to 10^6 rows (or
# the sizes given), 100 Hz, holds of 3-20 s (uniform) in random directions at least 30 deg apart,
# 1.5 s turns between them with a (1 - cos) profile, a triad of ~4000 counts/g with offsets near
# 32768, off-diagonal angles of a few mrad, 3 counts of white noise, rounded to counts. The logs
# are written by an embedded numpy generator (Debian's /usr/bin/python3) to a temporary folder,
# imu_tk's ASCII layout (t x y z), seed fixed per size.
#
# Each size: calibrate_imu --mode=ml (discovery, determination and covariance included: the
# default run) timed as a whole process by /usr/bin/time -v: wall time, CPU time (user + system)
# and peak RSS; then the growth exponent of wall and CPU time in the pose count (least squares on
# the logs, over the sizes from the second one up: the smallest is dominated by the start-up).
#
#   tools/bench/triad_scale_bench.sh [BIN_DIR] [ROWS ...]
#       BIN_DIR: default build/bin (calibrate_imu is not built here); ROWS default
#       100000 200000 500000 1000000
# Environment: ACCELCAL_SCALE_KEEP=1 keeps the temporary folder (its path is printed).
# Prints one table row per size: rows, poses (the poses calibrate_imu used), wall s, CPU s,
# peak RSS MB, exit status; then `exponent cpu=X wall=Y`.
set -euo pipefail
ACCELCAL_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin_dir=${1:-$ACCELCAL_ROOT/build/bin}
shift || true
sizes=("$@")
[ ${#sizes[@]} -eq 0 ] && sizes=(100000 200000 500000 1000000)
python=/usr/bin/python3
say() { echo "triad_scale_bench: $*" >&2; }
[ -x "$bin_dir/calibrate_imu" ] || { say "no $bin_dir/calibrate_imu"; exit 2; }
[ -x /usr/bin/time ] || { say "/usr/bin/time is needed (apt-get install time)"; exit 2; }
"$python" -c 'import numpy' 2>/dev/null || { say "$python with numpy is needed"; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/accelcal-triad-scale.XXXXXX")
if [ "${ACCELCAL_SCALE_KEEP:-0}" = 1 ]; then say "logs kept in $work"; else trap 'rm -rf "$work"' EXIT; fi

cat >"$work/generate.py" <<'EOF'
import sys
import numpy as np

rows, path, seed = int(sys.argv[1]), sys.argv[2], int(sys.argv[3])
rng = np.random.default_rng(seed)
rate_hz, turn_s, g = 100.0, 1.5, 9.81
gain = np.array([9.81 / 4000.0, 9.81 / 4050.0, 9.81 / 3950.0])  # (m/s^2) per count
offset = np.array([32768.0 + 40.0, 32768.0 - 25.0, 32768.0 + 10.0])
T = np.array([[1.0, -0.003, 0.002], [0.0, 1.0, -0.004], [0.0, 0.0, 1.0]])  # a = T K (u - b)
M = np.linalg.inv(T @ np.diag(gain))


def random_direction():
    v = rng.normal(size=3)
    return v / np.linalg.norm(v)


directions, pieces, count = [random_direction()], [], 0
while count < rows:
    n = directions[-1]
    hold = int(rng.uniform(3.0, 20.0) * rate_hz)
    pieces.append(np.tile(n, (hold, 1)))
    count += hold
    while True:
        m = random_direction()
        if np.degrees(np.arccos(np.clip(n @ m, -1, 1))) > 30.0:
            break
    turn = int(turn_s * rate_hz)
    axis = np.cross(n, m)
    axis /= np.linalg.norm(axis)
    angle = np.arccos(np.clip(n @ m, -1, 1))
    tau = np.arange(1, turn + 1) / turn
    phi = angle * (1 - np.cos(np.pi * tau)) / 2
    # Rodrigues: n rotated about axis (perpendicular to n) by phi
    turned = np.outer(np.cos(phi), n) + np.outer(np.sin(phi), np.cross(axis, n))
    pieces.append(turned)
    count += turn
    directions.append(m)
force = g * np.concatenate(pieces)[:rows]
u = force @ M.T + offset + rng.normal(scale=3.0, size=force.shape)
u = np.round(u)
t = np.arange(rows) / rate_hz
with open(path, "w") as f:
    np.savetxt(f, np.column_stack([t, u]), fmt=["%.2f", "%d", "%d", "%d"])
EOF

printf '%-9s %6s %9s %9s %9s %4s\n' rows poses wall_s cpu_s rss_MB rc
results=()
for rows in "${sizes[@]}"; do
  log="$work/hand_held_$rows.txt"
  "$python" "$work/generate.py" "$rows" "$log" "$rows"
  set +e
  /usr/bin/time -v -o "$work/time_$rows.txt" "$bin_dir/calibrate_imu" --log="$log" --g=9.81 \
      --mode=ml --json="$work/ml_$rows.json" >"$work/out_$rows.txt" 2>&1
  rc=$?
  set -e
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, p, ":"); s = 0;
           for (i = 1; i <= n; ++i) s = s * 60 + p[i]; print s}' "$work/time_$rows.txt")
  cpu=$(awk -F': ' '/User time/ {u = $2} /System time/ {s = $2} END {print u + s}' "$work/time_$rows.txt")
  rss=$(awk -F': ' '/Maximum resident/ {printf "%.0f", $2 / 1024}' "$work/time_$rows.txt")
  poses=$(sed -n 's/^poses: the \([0-9]*\) static intervals.*/\1/p' "$work/out_$rows.txt" | head -1)
  [ -n "$poses" ] || poses="?"
  printf '%-9s %6s %9.2f %9.2f %9s %4s\n' "$rows" "$poses" "$wall" "$cpu" "$rss" "$rc"
  results+=("$poses $wall $cpu")
done
printf '%s\n' "${results[@]}" | "$python" -c '
import sys, numpy as np
r = [l.split() for l in sys.stdin if l.strip()]
r = [(float(p), float(w), float(c)) for p, w, c in r if p not in ("?", "None")]
if len(r) >= 3: r = r[1:]
if len(r) < 2: sys.exit(0)
p = np.log([x[0] for x in r])
fit = lambda y: np.polyfit(p, np.log(y), 1)[0]
print("exponent cpu=%.2f wall=%.2f (in poses, %d sizes)" % (fit([x[2] for x in r]), fit([x[1] for x in r]), len(r)))'
