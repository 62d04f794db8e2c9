#!/usr/bin/env bash
# A run CSV read under a memory limit is read whole or refused in one line naming the file,
# never read in part (issue 15). The former reader copied the file through a stream buffer
# that swallowed std::bad_alloc: under ulimit -v 800000 the buffer failed to grow past
# 256 MiB, and a valid 6,000,000-sample run was integrated as its first 4,194,303 samples,
# exit 0.
#
#   low_memory_test.sh BIN_DIR GOOD_DIR
#
# Runs trajectory twice on a 384 MB CSV (about 10 s in all): under 800000 KiB, where the
# whole run fits, and under 500000 KiB, where it does not.
set -uo pipefail

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

bin=$1 good=$2
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
run=$scratch/trajectory.csv
# 64-byte lines after 64 bytes of comment and header: 256 MiB ends exactly at a line end,
# so a read cut there leaves no broken line behind to give it away.
{
  printf '#%054d\n' 0
  echo t,ax,ay
  seq -f "%018.12f,0.1234567890123456789,-0.2345678901234567890" 0 0.01 59999.99
} >"$run" || fail "cannot write $run"
[ "$(wc -l <"$run")" = 6000002 ] || fail "the generated run does not have 6000000 rows"

for limit in 800000 500000; do
  (
    ulimit -v "$limit"
    "$bin/trajectory" --data_dir="$good" --run_file="$run" >"$scratch/stdout" 2>"$scratch/stderr"
  )
  status=$?
  echo "ulimit -v $limit: trajectory exited $status; stderr:"
  cat "$scratch/stderr"
  if [ "$status" = 0 ]; then
    grep -q "(6000000 samples, " "$scratch/stdout" ||
      fail "exit 0 but not all 6000000 samples were read: $(grep -m1 ' run ' "$scratch/stdout")"
  elif [ "$status" = 2 ]; then
    [ "$(wc -l <"$scratch/stderr")" = 1 ] || fail "a refusal must be one line on stderr"
    grep -q "^trajectory: error: $run: not enough memory to " "$scratch/stderr" ||
      fail "the refusal must name the file and say that memory ran out"
  else
    fail "exit status $status, expected 0 (the whole run) or 2 (one line: not enough memory)"
  fi
done
echo "PASS"
