#!/usr/bin/env bash
# The rooms of src/ and which way their arrows point (docs/architecture.md): every
# #include "room/..." in src/ROOM must name ROOM itself or one of the rooms it may use.
# A new include that points outward (models including estimation, simulation including io)
# fails this test with the file and line.
# Usage: tests/layering_test.sh SOURCE_DIR
set -u
src=${1:?SOURCE_DIR}/src
declare -A may_use=(
  [common]=""
  [models]="common"
  [residuals]="common models"
  [estimation]="common models residuals"
  [simulation]="common models"
  [io]="common models simulation"
  [studies]="common models residuals estimation simulation"
  [reporting]="common models estimation studies io"
)
status=0
for room in "${!may_use[@]}"; do
  [ -d "$src/$room" ] || { echo "layering: src/$room is missing" >&2; status=1; continue; }
done
for dir in "$src"/*/; do
  room=$(basename "$dir")
  if [ -z "${may_use[$room]+set}" ]; then
    echo "layering: src/$room is a room docs/architecture.md and this test do not know" >&2
    status=1
    continue
  fi
  while IFS=: read -r file line include; do
    target=$(sed -E 's/.*#include "([a-z_]+)\/.*/\1/' <<<"$include")
    [ "$target" = "$room" ] && continue
    case " ${may_use[$room]} " in
      *" $target "*) ;;
      *)
        echo "layering: ${file#"$src"/}:$line: src/$room may not include $target/ (it may use: ${may_use[$room]:-nothing})" >&2
        status=1
        ;;
    esac
  done < <(grep -rnE '^#include "[a-z_]+/' "$dir" --include='*.h' --include='*.cc' --include='*.in')
done
[ $status = 0 ] && echo "layering: every include of src/ points inward"
exit $status
