#!/usr/bin/env bash
# Runs the trajectory binary on the course data and tools/plot_trajectory.py on its
# outputs; checks that the PNG is a valid image of a sensible size. Skips (exit 77)
# without the course data or matplotlib.
set -euo pipefail
bin_dir=$1
source_dir=$2
data=${ACCELCAL_COURSE_DATA:-$source_dir/../shared/data/tp2-2018}
[ -f "$data/ensayo.mat" ] || { echo "SKIP: course data not found at $data"; exit 77; }
/usr/bin/python3 -c "import matplotlib, numpy" 2>/dev/null || { echo "SKIP: no python3-matplotlib"; exit 77; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
"$bin_dir/trajectory" --data_dir="$data" --json="$scratch/t.json" --path_csv="$scratch/path.csv" >/dev/null
/usr/bin/python3 "$source_dir/tools/plot_trajectory.py" --json="$scratch/t.json" \
  --path_csv="$scratch/path.csv" --out="$scratch/trajectory.png" >/dev/null
/usr/bin/python3 - "$scratch/trajectory.png" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
width, height = struct.unpack(">II", data[16:24])
assert 600 <= width <= 3000 and 400 <= height <= 3000, (width, height)
assert len(data) > 20000, len(data)
print(f"trajectory.png {width}x{height}, {len(data)} bytes")
PY
