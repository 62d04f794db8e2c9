#!/usr/bin/env bash
# Runs one case of tests/data/bad_flags.txt through a real binary:
#
#   bad_flags_test.sh BIN_DIR GOOD_DIR CASES_FILE CASE
#
# The binary must end within 60 s with exit status 2 and one line on stderr matching the
# case's regex, and leave nothing at {out}. {good} is a valid data folder, {sparse} a 2 GB
# sparse file of zeros named .csv.
set -uo pipefail
bin_dir=$1 good=$2 cases=$3 name=$4
line=$(grep -E "^$name *\|" "$cases") || { echo "FAIL: no case '$name' in $cases" >&2; exit 1; }
command_line=$(echo "$line" | cut -d'|' -f2 | sed -E 's/^ +//; s/ +$//')
regex=$(echo "$line" | cut -d'|' -f3- | sed -E 's/^ +//; s/ +$//')
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
out="$scratch/out"
command_line=${command_line//\{out\}/$out}
command_line=${command_line//\{good\}/$good}
# {sparse}: a 2 GB sparse file of zeros (no disk space used), as a CSV.
if [[ $command_line == *"{sparse}"* ]]; then
  truncate -s 2G "$scratch/sparse.csv"
  command_line=${command_line//\{sparse\}/$scratch/sparse.csv}
fi
read -r -a argv <<<"$command_line"
timeout 60 "$bin_dir/${argv[0]}" "${argv[@]:1}" >"$scratch/stdout" 2>"$scratch/stderr"
status=$?
echo "case $name: ${argv[0]} exited $status; stderr:"
head -c 2000 "$scratch/stderr"
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
[ $status != 124 ] || fail "still running after 60 s"
[ $status = 2 ] || fail "exit status $status, expected 2"
[ "$(wc -l <"$scratch/stderr")" = 1 ] || fail "a refusal must be one line on stderr"
grep -Eq -- "$regex" "$scratch/stderr" || fail "stderr does not match: $regex"
[ ! -e "$out" ] || fail "a refusal left output behind at $out"
ls "$scratch" | grep -q '\.tmp\.' && fail "a refusal left a temporary file"
echo "PASS"
