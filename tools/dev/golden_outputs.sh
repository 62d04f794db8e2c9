#!/usr/bin/env bash
# Runs every problem binary on the course data and on the default simulation and writes what each
# printed and wrote (stdout, stderr, exit status, JSON, CSV, the analyze report) under OUT_DIR.
# Used to show that a restructuring changes no output: run it before and after, then
#   diff -r -I '"seconds"' -I ' s on [0-9]* thread' -I 'threads, [0-9.]* s)' BEFORE AFTER
# (timings are the only text that differs from run to run)
# Usage: tools/dev/golden_outputs.sh BIN_DIR OUT_DIR [COURSE_DATA_DIR]
set -u
bin=$(cd "${1:?BIN_DIR}" && pwd); out=${2:?OUT_DIR}
data=${3:-$(cd "$(dirname "$0")/../.." && pwd)/../shared/data/tp2-2018}
tools=$(cd "$(dirname "$0")/.." && pwd)
rm -rf "$out"; mkdir -p "$out"
run() {  # name, binary, flags...
  local name=$1; shift
  local b=$1; shift
  (cd "$out" && "$bin/$b" "$@" >"$name.stdout" 2>"$name.stderr"; echo $? >"$name.rc")
  # the data folder's absolute path and the output folder's are the only machine-dependent text
  sed -i -e "s#$data#DATA#g" -e "s#$out#OUT#g" "$out/$name".std* 2>/dev/null
}
for src in course sim; do
  d=(); [ $src = course ] && d=(--data_dir="$data")
  run $src.linear_ls linear_ls "${d[@]}" --json=$src.linear_ls.json
  run $src.trajectory trajectory "${d[@]}" --json=$src.trajectory.json --path_csv=$src.path.csv
  run $src.joint joint "${d[@]}" --json=$src.joint.json
  run $src.joint_all joint "${d[@]}" --effects=all --json=$src.joint_all.json
  run $src.discover discover "${d[@]}" --json=$src.discover.json --bins_csv=$src.bins.csv \
      --residuals_csv=$src.residuals.csv
  run $src.min_samples min_samples "${d[@]}" --json=$src.min_samples.json --repetitions=200
  run $src.analyze analyze "${d[@]}" --out_dir=$src.report --python=/usr/bin/python3 \
      --tools_dir="$tools"
done
run sim_set.discover discover --set=angle_offset=0.004,nonorthogonality=0.003 --json=sim_set.discover.json
run sim_set.joint joint --set=angle_offset=0.004 --effects=angle_offset --json=sim_set.joint.json
run simulate simulate --out_dir=simulated --seed=3
run simulate_csv simulate --out_dir=simulated_csv --format=csv --seed=3
run coverage coverage --trials=40 --effect_trials=10 --json=coverage.json
run power power --trials=10 --sizes=3 --json=power.json
run null_rate null_rate --datasets=20 --json=null_rate.json
# The triad (and its discovery) on the shared real logs and a small simulated study.
shared=$(cd "$data/.." && pwd)
xsens="$shared/imu_tk-xsens/xsens_acc.mat"
mimu="$shared/mimu4444"
if [ -f "$xsens" ]; then
  run xsens.imu_tk calibrate_imu --log="$xsens" --g=9.81744 --mode=imu_tk --json=xsens.imu_tk.json
  run xsens.ml calibrate_imu --log="$xsens" --g=9.81744 --mode=ml --json=xsens.ml.json \
      --calibration_out=xsens.cal.json
  run xsens.ml_white calibrate_imu --log="$xsens" --g=9.81744 --mode=ml --noise=white \
      --json=xsens.ml_white.json
  run xsens.allan allan --log="$xsens" --static=all --bootstrap=200 --json=xsens.allan.json
  run xsens.apply apply --calibration=xsens.cal.json --in="$xsens" --out=xsens.corrected.csv
  # Both sensors: the gyroscope by maximum likelihood (with discovery) and imu_tk's rules.
  xsens_gyro="$shared/imu_tk-xsens/xsens_gyro.mat"
  run xsens.gyro_ml calibrate_imu --log="$xsens" --gyro_log="$xsens_gyro" --g=9.81744 \
      --init_rest_s=50 --initial_gyro_gain=0.00015979546180888463 --mode=ml \
      --json=xsens.gyro_ml.json --calibration_out=xsens.gyro_cal.json
  run xsens.gyro_imu_tk calibrate_imu --log="$xsens" --gyro_log="$xsens_gyro" --g=9.81744 \
      --init_rest_s=50 --initial_gyro_gain=0.00015979546180888463 --mode=imu_tk \
      --json=xsens.gyro_imu_tk.json
fi
if [ -d "$mimu" ]; then
  for session in run1/imu1 run3/imu4 run2/imu7; do
    name=mimu.${session/\//.}
    run "$name" calibrate_imu --log="$mimu/$session.csv" --g=9.8187 --mode=ml --json="$name.json"
  done
  run mimu.sessions calibrate_imu --log="$mimu/run1/imu1.csv,$mimu/run2/imu1.csv,$mimu/run3/imu1.csv" \
      --g=9.8187 --mode=ml --json=mimu.sessions.json
fi
run triad_study triad_study --trials=40 --json=triad_study.json
sed -i -e "s#$shared#SHARED#g" "$out"/*.std* 2>/dev/null
# PNG files carry no date but matplotlib may change them across versions; keep their checksums
find "$out" -name '*.png' -exec sh -c 'sha256sum < "$1" > "$1.sha256" && rm "$1"' _ {} \;
