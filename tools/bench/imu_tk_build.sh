# Sourced by tools/bench/imu_tk_peer.sh and tools/bench/imu_tk_scale_bench.sh: imu_tk's source
# checked (imu_tk_check_source) and its example built once (imu_tk_build), as imu_tk_peer.sh's
# header describes (the two patches, the flags, the cache and its stamp). Both functions use `say`
# from the caller and exit 2 on failure.
#
# imu_tk_check_source: reads ACCELCAL_IMU_TK_SOURCE; sets imu_tk_source and source_kind
#   (tree or git).
# imu_tk_build CACHE: builds test_imu_calib in CACHE (or finds it built); sets imu_tk_bin,
#   imu_tk_id (the source's commit and place), cxx and cxxflags.

imu_tk_check_source() {
  imu_tk_source=${ACCELCAL_IMU_TK_SOURCE:-}
  imu_tk_files=(apps/test_imu_calib.cpp src/calibration.cpp src/filters.cpp src/io_utils.cpp
    include/imu_tk/calibration.h)
  source_kind=""
  if [ -z "$imu_tk_source" ]; then
    say "ACCELCAL_IMU_TK_SOURCE is not set: set it to imu_tk's source tree or git directory (github.com/iralabdisco/imu_tk)"
    exit 2
  elif [ -f "$imu_tk_source/apps/test_imu_calib.cpp" ]; then
    source_kind=tree
    for f in "${imu_tk_files[@]}"; do
      if [ ! -f "$imu_tk_source/$f" ]; then
        say "ACCELCAL_IMU_TK_SOURCE=$imu_tk_source is not imu_tk's source: it has no $f"
        exit 2
      fi
    done
  elif git --git-dir="$imu_tk_source" cat-file -e HEAD:apps/test_imu_calib.cpp 2>/dev/null; then
    source_kind=git
  else
    say "ACCELCAL_IMU_TK_SOURCE=$imu_tk_source is neither an imu_tk source tree nor a git directory with imu_tk at HEAD (no apps/test_imu_calib.cpp)"
    exit 2
  fi
}

imu_tk_build() {
  cache=$1
  cxx=g++
  cxxflags=(-std=gnu++17 -O3 -DNDEBUG -I/usr/include/eigen3)
  ldlibs=(-lceres -lglog)
  mkdir -p "$cache"
  cache=$(cd "$cache" && pwd)
  rm -rf "$cache/pristine.new"
  mkdir -p "$cache/pristine.new"
  if [ "$source_kind" = git ]; then
    imu_tk_id="$(git --git-dir="$imu_tk_source" rev-parse HEAD) of $imu_tk_source"
    git --git-dir="$imu_tk_source" archive HEAD apps src include | tar -x -C "$cache/pristine.new"
  else
    imu_tk_id=$imu_tk_source
    if git -C "$imu_tk_source" rev-parse HEAD >/dev/null 2>&1; then
      imu_tk_id="$(git -C "$imu_tk_source" rev-parse HEAD) in $imu_tk_source"
    fi
    cp -r "$imu_tk_source/apps" "$imu_tk_source/src" "$imu_tk_source/include" "$cache/pristine.new/"
  fi
  # What the build depends on: imu_tk's files, the patches (their version: change it when they
  # change), the flags and the compiler.
  patches_version=1
  stamp=$({
    (cd "$cache/pristine.new" && find apps src include -type f -print0 | sort -z | xargs -0 sha256sum)
    echo "patches $patches_version; $cxx ${cxxflags[*]} ${ldlibs[*]}"
    "$cxx" --version | head -1
  } | sha256sum | cut -d' ' -f1)
  imu_tk_bin=$cache/test_imu_calib
  if [ -x "$imu_tk_bin" ] && [ "$(cat "$cache/stamp" 2>/dev/null)" = "$stamp" ]; then
    rm -rf "$cache/pristine.new"
    say "imu_tk's example: built already ($imu_tk_bin)"
  else
    say "building imu_tk's example in $cache (g++ -O3, about 12 s of CPU; log: $cache/build.log)"
    rm -rf "$cache/pristine" "$cache/patched" "$cache/obj" "$cache/stamp" "$imu_tk_bin"
    mv "$cache/pristine.new" "$cache/pristine"
    cp -r "$cache/pristine" "$cache/patched"
    p=$cache/patched
    # Patch 1: the plot and the wait for Enter in calibrateAcc's verbose branch.
    sed -i -e '/^[[:space:]]*Plot plot;[[:space:]]*$/d' \
      -e '/^[[:space:]]*plot\.plotIntervals( calib_acc_samples_, min_cost_static_intervals_);[[:space:]]*$/d' \
      -e '/^[[:space:]]*waitForKey();[[:space:]]*$/d' "$p/src/calibration.cpp"
    # Patch 2: the setter that returns nothing though declared to return _T.
    sed -i 's/^\([[:space:]]*\)_T setInitStaticIntervalDuration( _T duration )/\1void setInitStaticIntervalDuration( _T duration )/' \
      "$p/include/imu_tk/calibration.h"
    removed=$(diff "$cache/pristine/src/calibration.cpp" "$p/src/calibration.cpp" | grep -c '^<' || true)
    if [ "$removed" != 3 ] || grep -q 'plot\|waitForKey' "$p/src/calibration.cpp" ||
      ! grep -q 'void setInitStaticIntervalDuration' "$p/include/imu_tk/calibration.h"; then
      say "the patches did not apply as written (this imu_tk differs from the one they were made for); see $p"
      exit 2
    fi
    mkdir -p "$cache/obj"
    : >"$cache/build.log"
    for tu in src/calibration.cpp src/filters.cpp src/io_utils.cpp apps/test_imu_calib.cpp; do
      if ! "$cxx" "${cxxflags[@]}" -I"$p/include" -c "$p/$tu" -o "$cache/obj/$(basename "$tu" .cpp).o" \
        >>"$cache/build.log" 2>&1; then
        grep -E -A4 'error' "$cache/build.log" | head -40 >&2
        say "compiling imu_tk's $tu failed; the full log is $cache/build.log"
        exit 2
      fi
    done
    if ! "$cxx" -o "$imu_tk_bin" "$cache"/obj/*.o "${ldlibs[@]}" >>"$cache/build.log" 2>&1; then
      tail -20 "$cache/build.log" >&2
      say "linking imu_tk's example failed; the full log is $cache/build.log"
      exit 2
    fi
    echo "$stamp" >"$cache/stamp"
  fi
}
