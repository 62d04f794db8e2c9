#!/usr/bin/env bash
# Headless screenshots of a report.html at a desktop width (1280 px) and a phone width (390 px),
# to look at before a change to the report's layout is committed: no table cut off (a wide table
# scrolls inside its wrapper), figures legible. A developer's check, not a test: it needs
# Debian's chromium (apt-get install chromium), which neither tools/test.sh nor tools/run.sh
# installs.
#
# Each width gets the whole page in one PNG (OUT_DIR/report-<width>.png) and, with Python's PIL
# (python3-pil, which matplotlib brings), the blank bottom cut off and the page cut into pieces
# of at most 2000 px (OUT_DIR/report-<width>-<k>.png) that an image viewer shows at full size.
# It also says when the page is wider than the window (something not wrapped or scrolled).
#
# Usage: tools/dev/screenshot_report.sh REPORT_HTML OUT_DIR
set -euo pipefail
html=$(realpath "${1:?REPORT_HTML}")
out=${2:?OUT_DIR}
mkdir -p "$out"
out=$(realpath "$out")
browser=$(command -v chromium || command -v chromium-browser || true)
[ -n "$browser" ] || { echo "screenshot_report.sh: no chromium (apt-get install -y chromium)" >&2; exit 2; }
python=/usr/bin/python3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
flags=(--headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir="$work/profile")

# The page's height at a width, and whether anything is wider than the page's body there: a
# copy of the page laid out at that width (headless chromium's window is at least 500 px wide
# in --dump-dom mode, so the width is set on <html>; the media queries see a phone's viewport
# either way) that writes its sizes into the DOM once loaded, read back with --dump-dom.
page_size_at() {  # width -> "OVERFLOW_PX HEIGHT"
  sed -e "s#</head>#<style>html{width:${1}px}</style></head>#" \
    -e 's#</body>#<script>addEventListener("load",function(){var b=document.body;document.body.setAttribute("data-page-size",(b.scrollWidth-b.clientWidth)+"x"+document.documentElement.scrollHeight)})</script></body>#' \
    "$html" >"$work/measure.html"
  "$browser" "${flags[@]}" --window-size="$1,1000" --virtual-time-budget=5000 --dump-dom \
    "file://$work/measure.html" 2>/dev/null | grep -o 'data-page-size="[-0-9x]*"' |
    grep -o '[-0-9]*x[0-9]*' | tr x ' '
}

for width in 1280 390; do
  read -r overflow page_height < <(page_size_at "$width") || true
  [ -n "${page_height:-}" ] || { echo "screenshot_report.sh: could not measure the page at $width px" >&2; exit 1; }
  [ "$overflow" -le 0 ] ||
    echo "screenshot_report.sh: at $width px something is $overflow px wider than the page: cut off" >&2
  # Room to spare; the blank bottom is cut off below.
  height=$((page_height + 500))
  png="$out/report-$width.png"
  rm -f "$out/report-$width-"*.png
  "$browser" "${flags[@]}" --window-size="$width,$height" --virtual-time-budget=5000 \
    --screenshot="$png" "file://$html" 2>/dev/null
  if ! "$python" -c 'import PIL' 2>/dev/null; then
    echo "$png (${width}x${height}, blank bottom not cut: no python3-pil)"
    continue
  fi
  "$python" - "$png" <<'PYTHON'
import sys
from PIL import Image, ImageChops
path = sys.argv[1]
image = Image.open(path).convert("RGB")
box = ImageChops.difference(image, Image.new("RGB", image.size, "white")).getbbox()
if box is not None:
    image = image.crop((0, 0, image.width, min(image.height, box[3] + 24)))
    image.save(path)
print("%s (%dx%d)" % (path, image.width, image.height))
page = 2000
for k, top in enumerate(range(0, image.height, page), start=1):
    name = path[:-4] + "-%d.png" % k
    image.crop((0, top, image.width, min(image.height, top + page))).save(name)
    print("  " + name)
PYTHON
done
