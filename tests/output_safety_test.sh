#!/usr/bin/env bash
# Outputs never destroy inputs, special files or folders accelcal did not write; no shell
# sees a path; an interrupted or limited run leaves no temporary file; several outputs are
# written all or none:
#
#   output_safety_test.sh BIN_DIR GOOD_DIR TOOLS_DIR
#
# GOOD_DIR is a small valid data folder (course layout). Every check runs on copies in a
# scratch folder; the checks of /dev/null run in a private mount namespace whose /dev is a
# tmpfs (root only), so a failure could never touch the machine's own /dev/null.
set -uo pipefail
bin_dir=$1 good=$2 tools_dir=$3
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"
failures=0
fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}
pass() { echo "ok: $*"; }

cp -r "$good" data
checksum() { find "$1" -type f -print0 | sort -z | xargs -0 sha256sum | sha256sum; }
data_sum=$(checksum data)

# refuse NAME EXPECTED_REGEX COMMAND...: exit status 2, one line matching, the data intact.
refuse() {
  local name=$1 regex=$2
  shift 2
  "$@" >stdout 2>stderr
  local status=$?
  if [ $status != 2 ]; then
    fail "$name: exit status $status, expected 2 ($(head -c 300 stderr))"
  elif [ "$(wc -l <stderr)" != 1 ] || ! grep -Eq -- "$regex" stderr; then
    fail "$name: stderr is not one line matching '$regex': $(head -c 300 stderr)"
  elif [ "$(checksum data 2>/dev/null)" != "$data_sum" ]; then
    fail "$name: the data folder changed"
  else
    pass "$name: $(cat stderr)"
  fi
  # Put the data back if a failing binary damaged it, so that the next check tests its own case.
  if [ "$(checksum data 2>/dev/null)" != "$data_sum" ]; then
    rm -rf data && cp -r "$good" data
  fi
}

# --- inputs and their folders ---
refuse "analyze into the data folder with --overwrite" "holds the input" \
  "$bin_dir/analyze" --data_dir=data --out_dir=data --overwrite
mkdir parent && cp -r "$good" parent/data
parent_sum=$(checksum parent)
refuse "analyze into the data folder's parent" "holds the input" \
  "$bin_dir/analyze" --data_dir=parent/data --out_dir=parent --overwrite
[ "$(checksum parent 2>/dev/null)" = "$parent_sum" ] || fail "the data folder's parent changed"
refuse "analyze into a folder inside the data" "lies inside the data folder" \
  "$bin_dir/analyze" --data_dir=data --out_dir=data/report --overwrite
refuse "trajectory --json over an input" "is the input" \
  "$bin_dir/trajectory" --data_dir=data --json=data/datos.txt
ln data/acel.mat hardlink.mat
refuse "trajectory --json over a hard link to an input" "is the input" \
  "$bin_dir/trajectory" --data_dir=data --json=hardlink.mat
refuse "linear_ls --json over its calibration file" "is the input" \
  "$bin_dir/linear_ls" --calibration_file=data/ensayo.mat --conditions_file=data/datos.txt \
  --json=data/ensayo.mat
# simulate never writes over the folder holding its own scenario.
"$bin_dir/simulate" --format=csv --set=tilt_samples=50,run_duration=1 --out_dir=csvdata >/dev/null ||
  fail "could not simulate a CSV folder"
csv_sum=$(checksum csvdata)
"$bin_dir/simulate" --scenario=csvdata/scenario.json --out_dir=csvdata --overwrite >stdout 2>stderr
[ $? = 2 ] && [ "$(checksum csvdata)" = "$csv_sum" ] && pass "simulate never replaces its scenario's folder" ||
  fail "simulate --overwrite over its scenario's folder: $(cat stderr)"

# --- special files and links ---
mkfifo fifo
refuse "trajectory --json to a FIFO" "is a FIFO" "$bin_dir/trajectory" --data_dir=data --json=fifo
[ -p fifo ] || fail "the FIFO was replaced"
echo keep >target.json
ln -s target.json link.json
refuse "trajectory --json to a symbolic link" "is a symbolic link" \
  "$bin_dir/trajectory" --data_dir=data --json=link.json
[ -L link.json ] && [ "$(cat target.json)" = keep ] || fail "the link or its target changed"
ln -s fifo fifo_link
refuse "trajectory --json to a link to a FIFO" "is a symbolic link" \
  "$bin_dir/trajectory" --data_dir=data --json=fifo_link
mkdir linked_dir_target && ln -s linked_dir_target linked_dir
refuse "analyze --out_dir a symbolic link to a folder" "not a folder|symbolic link" \
  "$bin_dir/analyze" --data_dir=data --out_dir=linked_dir --overwrite
if [ "$(id -u)" = 0 ] && unshare --mount --propagation private true 2>/dev/null; then
  # /dev is a tmpfs of this namespace only: its null is a real character device, and a
  # binary that replaced it would leave a regular file there.
  unshare --mount --propagation private bash -c '
    mount -t tmpfs none /dev && mknod -m 666 /dev/null c 1 3 && mknod -m 666 /dev/zero c 1 5 &&
    mknod -m 666 /dev/urandom c 1 9 || exit 3
    "$1/trajectory" --data_dir=data --json=/dev/null 2>stderr; status=$?
    [ -c /dev/null ] || exit 4
    [ $status = 2 ] || exit 5
    mknod devnull c 1 3
    "$1/linear_ls" --data_dir=data --json=devnull 2>>stderr; status=$?
    [ -c devnull ] || exit 6
    [ $status = 2 ] || exit 7' _ "$bin_dir"
  status=$?
  [ $status = 0 ] && pass "/dev/null and a device node are never replaced: $(cat stderr | tr '\n' ' ')" ||
    fail "/dev/null check (step $status): $(cat stderr 2>/dev/null)"
else
  echo "skip: /dev/null in a mount namespace needs root and unshare"
fi

# --- --overwrite replaces only what accelcal wrote ---
mkdir mine && echo precious >mine/notes.txt
refuse "analyze --overwrite of a folder accelcal did not write" "not written by accelcal" \
  "$bin_dir/analyze" --data_dir=data --out_dir=mine --overwrite
[ "$(cat mine/notes.txt)" = precious ] || fail "--overwrite deleted a folder accelcal did not write"
"$bin_dir/simulate" --out_dir=sim --set=tilt_samples=50,run_duration=1 >/dev/null &&
  "$bin_dir/simulate" --out_dir=sim --set=tilt_samples=60,run_duration=1 --overwrite >/dev/null &&
  pass "--overwrite replaces a folder accelcal wrote" || fail "--overwrite of accelcal's own folder"

# --- no shell: a folder name with quotes, spaces and ';' is a name ---
weird="it's a \"dir\"; touch PWNED; \$(touch PWNED2)"
mkdir -p "$weird"
"$bin_dir/analyze" --data_dir=data --out_dir="$weird/report" --tools_dir="$tools_dir" >stdout 2>stderr
status=$?
if [ $status != 0 ]; then
  fail "analyze into '$weird/report': exit $status: $(cat stderr)"
elif ls PWNED* "$weird"/PWNED* 2>/dev/null | grep -q .; then
  fail "a shell ran a command from the folder name"
elif [ -s stderr ]; then
  fail "analyze printed on stderr: $(cat stderr)"
elif ! [ -s "$weird/report/trajectory.png" ] || grep -q "Figures not drawn" "$weird/report/report.md"; then
  fail "the figures were not drawn in '$weird/report'"
else
  pass "a folder named '$weird' gets its report and figures, and no command ran"
fi

# --- interrupted: SIGTERM and SIGINT while the report is written leave nothing behind ---
for signal in TERM INT; do
  out="interrupted_$signal"
  landed=0
  for attempt in 1 2 3 4 5; do
    "$bin_dir/analyze" --data_dir=data --out_dir="$out" --tools_dir="$tools_dir" >/dev/null 2>&1 &
    pid=$!
    # Wait until the temporary folder exists, i.e. the report is being written.
    for _ in $(seq 1 3000); do
      ls -d "$out".tmp.* >/dev/null 2>&1 && break
      kill -0 $pid 2>/dev/null || break
      sleep 0.01
    done
    if ls -d "$out".tmp.* >/dev/null 2>&1; then
      kill -$signal $pid
      wait $pid
      status=$?
      landed=1
      break
    fi
    wait $pid
    rm -rf "$out"
  done
  if [ $landed = 0 ]; then
    fail "SIG$signal: never caught analyze while it wrote"
    continue
  fi
  leftovers=$(ls -d "$out"* 2>/dev/null)
  expected=$((128 + $(kill -l $signal)))
  if [ "$status" != "$expected" ]; then
    fail "SIG$signal mid-write: exit status $status, expected $expected"
  elif [ -n "$leftovers" ]; then
    fail "SIG$signal mid-write left: $leftovers"
  else
    pass "SIG$signal mid-write: the run ended by the signal and left nothing"
  fi
done

# --- a file-size limit (ulimit -f) is an error, not a crash that leaves temporary files ---
(
  ulimit -f 8  # 8 blocks of 512 bytes: path.csv is larger
  "$bin_dir/trajectory" --data_dir=data --json=limited.json --path_csv=limited.csv --path_stride=1
) >stdout 2>stderr
status=$?
leftovers=$(ls limited* 2>/dev/null)
if [ $status != 2 ] || [ -n "$leftovers" ] || [ "$(wc -l <stderr)" != 1 ]; then
  fail "ulimit -f: exit $status, left '$leftovers', stderr: $(cat stderr)"
else
  pass "ulimit -f: $(cat stderr); nothing left"
fi

# --- several outputs: all or none ---
refuse "trajectory --json with an unwritable --path_csv" "path_csv" \
  "$bin_dir/trajectory" --data_dir=data --json=both.json --path_csv=missing_folder/path.csv
[ -e both.json ] && fail "the JSON was left behind"
chmod 555 .
if [ "$(id -u)" != 0 ]; then
  refuse "discover into a read-only folder" "cannot create" \
    "$bin_dir/discover" --data_dir=data --json=d.json --bins_csv=b.csv
fi
chmod 755 .
refuse "two outputs on one path" "overlaps another output" \
  "$bin_dir/discover" --data_dir=data --json=same.out --bins_csv=same.out

[ $failures = 0 ] && echo "PASS" || { echo "$failures check(s) failed"; exit 1; }
