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
# check_rooms PARENT RULES: every folder of src/PARENT (PARENT empty: of src/) is a room of the
# associative array named RULES, and each #include "PARENTroom/..." in it names the room itself
# or one RULES lets it use.
check_rooms() {
  local parent=$1
  local -n rules=$2
  local dir room file line include target
  for dir in "$src/$parent"*/; do
    room=$(basename "$dir")
    if [ -z "${rules[$room]+set}" ]; then
      echo "layering: src/$parent$room is a room docs/architecture.md and this test do not know" >&2
      status=1
      continue
    fi
    while IFS=: read -r file line include; do
      target=$(sed -E "s|.*#include \"$parent([a-z_]+)/.*|\\1|" <<<"$include")
      [ "$target" = "$room" ] && continue
      case " ${rules[$room]} " in
        *" $target "*) ;;
        *)
          echo "layering: ${file#"$src"/}:$line: src/$parent$room may not include $parent$target/ (it may use: ${rules[$room]:-nothing})" >&2
          status=1
          ;;
      esac
    done < <(grep -rnE "^#include \"$parent[a-z_]+/" "$dir" --include='*.h' --include='*.cc' --include='*.in')
  done
}
check_rooms "" may_use
# Inside estimation/, the same rule one level down: the shared statistics and solver helpers,
# the discovery procedure over them, and a room per sensor geometry, which may not include one
# another's files (the gyroscope's poses are the accelerometer triad's, so it may use triad/).
declare -A estimation_may_use=(
  [statistics]=""
  [solver]="statistics"
  [discovery]="statistics solver"
  [tilt_table]="statistics solver discovery"
  [triad]="statistics solver discovery"
  [gyroscope]="statistics solver discovery triad"
)
for file in "$src"/estimation/*.h "$src"/estimation/*.cc; do
  [ -e "$file" ] || continue
  echo "layering: ${file#"$src"/} is in no room of estimation/ (statistics, solver, discovery, tilt_table, triad, gyroscope)" >&2
  status=1
done
check_rooms estimation/ estimation_may_use
[ $status = 0 ] && echo "layering: every include of src/ points inward"
exit $status
