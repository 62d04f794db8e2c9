#!/usr/bin/env bash
# discover with an effect hidden, then tools/plot_discovery.py on its outputs: the PNG is a
# valid image of a sensible size, no wider than the report shows it. Skips (exit 77) without matplotlib.
set -euo pipefail
bin_dir=$1
source_dir=$2
/usr/bin/python3 -c "import matplotlib, numpy" 2>/dev/null || { echo "SKIP: no python3-matplotlib"; exit 77; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
"$bin_dir/discover" --set=angle_offset=0.004 --json="$scratch/d.json" --bins_csv="$scratch/bins.csv" >/dev/null
/usr/bin/python3 "$source_dir/tools/plot_discovery.py" --json="$scratch/d.json" --bins_csv="$scratch/bins.csv" \
  --out="$scratch/discovery.png" >/dev/null
/usr/bin/python3 - "$scratch/discovery.png" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
width, height = struct.unpack(">II", data[16:24])
# The report shows it ~900-1100 px wide: drawn much wider, its text shrinks below legibility
# (issue 18: 1760 px wide, ~6 px text).
assert 1000 <= width <= 1300 and 400 <= height <= 3000, (width, height)
assert len(data) > 30000, len(data)
print(f"discovery.png {width}x{height}, {len(data)} bytes")
PY
