#!/usr/bin/env bash
# tools/plot_min_samples.py on min_samples' JSON with and without Monte Carlo checks: the PNG is
# a valid image, and its title (kept in the PNG's Title metadata) names exactly the markers the
# figure draws (issue 18: it promised circles, squares and x's on a figure with none).
# Skips (exit 77) without matplotlib.
set -euo pipefail
bin_dir=$1
source_dir=$2
/usr/bin/python3 -c "import matplotlib, numpy" 2>/dev/null || { echo "SKIP: no python3-matplotlib"; exit 77; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
"$bin_dir/min_samples" --repetitions=0 --json="$scratch/none.json" >/dev/null
"$bin_dir/min_samples" --repetitions=20 --json="$scratch/checked.json" >/dev/null
for name in none checked; do
  /usr/bin/python3 "$source_dir/tools/plot_min_samples.py" --json="$scratch/$name.json" \
    --out="$scratch/$name.png" >/dev/null
done
/usr/bin/python3 - "$scratch" <<'PY'
import json, struct, sys, zlib

def title(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    at = 8
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b"tEXt" and body.startswith(b"Title\0"):
            return body[6:].decode("latin-1")
        if kind == b"zTXt" and body.startswith(b"Title\0"):
            return zlib.decompress(body[7:]).decode("latin-1")
        at += 12 + length
    raise AssertionError(f"{path}: no Title in the PNG")

scratch = sys.argv[1]
none = title(f"{scratch}/none.png")
for promise in ("circles", "squares", "x:"):
    assert promise not in none, (promise, none)
assert "analytic curves only" in none, none
checked = title(f"{scratch}/checked.png")
result = json.load(open(f"{scratch}/checked.json"))
kinds = {check["kind"] for design in result["designs"] for check in design["monte_carlo"]}
assert kinds, "min_samples --repetitions=20 made no Monte Carlo check"
assert ("circles" in checked) == ("full_simulation" in kinds), (kinds, checked)
assert ("squares" in checked) == any(k.startswith("real_test") for k in kinds), (kinds, checked)
assert "x: the analytic value" in checked, checked
print("titles:", none, "|", checked)
PY
