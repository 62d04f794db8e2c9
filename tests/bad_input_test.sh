#!/usr/bin/env bash
# Runs one case of the bad-input corpus (tests/data/bad/cases.txt) through a real binary and
# checks its exit status, its stderr and what it left behind:
#
#   bad_input_test.sh BIN_DIR GOOD_DIR CORPUS_DIR CASE
#   bad_input_test.sh --every-file-has-a-case CORPUS_DIR
#
# A refusal (non-zero exit) must be exactly one line "<binary>: error: <file>: ..." matching the
# case's regex, and leave no output. Success must leave the output (valid JSON without NaN or
# Infinity when it is a file), and its stderr must match the regex (^$: nothing at all).
set -uo pipefail

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

if [ "$1" = "--every-file-has-a-case" ]; then
  corpus=$2
  missing=0
  for path in "$corpus"/*; do
    file=$(basename "$path")
    case "$file" in make_corpus.py | cases.txt) continue ;; esac
    if ! grep -Eq "^[a-z0-9_]+ *\| *${file//./\\.} *\|" "$corpus/cases.txt"; then
      echo "FAIL: $file has no case in cases.txt" >&2
      missing=1
    fi
  done
  exit $missing
fi

bin_dir=$1 good=$2 corpus=$3 name=$4
line=$(grep -E "^$name *\|" "$corpus/cases.txt") || fail "no case '$name' in $corpus/cases.txt"
field() { echo "$line" | awk -F'|' -v n="$1" '{ gsub(/^ +| +$/, "", $n); print $n }'; }
file=$(field 2)
command_line=$(field 3)
expected_status=$(field 4)
# The regex is everything after the fourth '|' (it may contain '|' itself).
regex=$(echo "$line" | cut -d'|' -f5- | sed -E 's/^ +//; s/ +$//')

bad="$corpus/$file"
[ -f "$bad" ] || fail "corpus file $bad is missing"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
out="$scratch/out/result"
mkdir -p "$scratch/out"
# Case lines hold no quotes or spaces inside an argument, so word splitting is enough.
command_line=${command_line//\{bad\}/$bad}
# {good+bad=NAME}: a copy of the good folder with the corpus file in place of NAME.
if [[ $command_line =~ \{good\+bad=([A-Za-z0-9_.]+)\} ]]; then
  mixed="$scratch/mixed"
  cp -r "$good" "$mixed"
  cp "$bad" "$mixed/${BASH_REMATCH[1]}"
  command_line=${command_line//"${BASH_REMATCH[0]}"/$mixed}
  bad="$mixed/${BASH_REMATCH[1]}"
fi
command_line=${command_line//\{good\}/$good}
command_line=${command_line//\{out\}/$out}
read -r -a argv <<<"$command_line"
binary=${argv[0]}
"$bin_dir/$binary" "${argv[@]:1}" >"$scratch/stdout" 2>"$scratch/stderr"
status=$?
stderr=$(cat "$scratch/stderr")

echo "case $name: $binary exited $status; stderr:"
echo "$stderr"
[ "$status" = "$expected_status" ] || fail "exit status $status, expected $expected_status"
if [ "$regex" = '^$' ]; then
  [ -z "$stderr" ] || fail "expected an empty stderr"
else
  grep -Eq -- "$regex" <<<"$stderr" || fail "stderr does not match: $regex"
fi

if [ "$status" != 0 ]; then
  [ "$(wc -l <"$scratch/stderr")" = 1 ] || fail "a refusal must be one line on stderr"
  grep -q "^$binary: error: " <<<"$stderr" || fail "the line must start with '$binary: error: '"
  # Solver failures (cases named solver_*) are about the data as a whole, not one file.
  if [[ $name != solver_* ]]; then
    grep -qF -- "$bad" <<<"$stderr" || fail "the message must name the file $bad"
  fi
  leftovers=$(ls -A "$scratch/out")
  [ -z "$leftovers" ] || fail "a refusal left output behind: $leftovers"
else
  [ -e "$out" ] || fail "success but no output at $out"
  if [ -f "$out" ]; then
    /usr/bin/python3 -c '
import json, sys
def refuse(token):
    raise ValueError("non-finite number " + token)
json.load(open(sys.argv[1]), parse_constant=refuse)' "$out" || fail "the output is not valid finite JSON"
  fi
fi
echo "PASS"
