#!/usr/bin/env bash
# min_samples --help defines each design it offers, and every docs/*.md a binary's --help points
# at exists (issue 18: it pointed at a docs/min_samples.md that did not exist and never said
# what `four` and `two` are).
set -euo pipefail
bin_dir=$1
source_dir=$2
# gflags' --help exits 1: the text is what counts.
help=$( ("$bin_dir/min_samples" --helpshort 2>&1 || true) | tr -s ' \n' ' ')
for definition in "uniform (N samples evenly over one turn" "four (N/4 static samples" \
                  "two (N/2 at each of" "optimal (N/2 at each of the two positions"; do
  case "$help" in
    *"$definition"*) ;;
    *) echo "min_samples --helpshort does not define: $definition"; exit 1 ;;
  esac
done
status=0
for binary in "$bin_dir"/*; do
  [ -x "$binary" ] && [ -f "$binary" ] || continue
  for doc in $( ("$binary" --help 2>&1 || true) | { grep -o 'docs/[A-Za-z0-9_.-]*\.md' || true; } | sort -u); do
    if [ ! -f "$source_dir/$doc" ]; then
      echo "$(basename "$binary") --help points at $doc, which does not exist"
      status=1
    fi
  done
done
exit $status
