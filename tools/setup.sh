#!/usr/bin/env bash
# Shared set-up for tools/run.sh and tools/test.sh: install the Debian packages that are
# missing (quiet when all are present), then configure and build in Release into build/.
# Sourced, not executed.

ACCELCAL_PACKAGES=(
  build-essential cmake pkg-config
  libceres-dev libeigen3-dev libgflags-dev libgoogle-glog-dev
  libgtest-dev libgmock-dev libmatio-dev zlib1g-dev nlohmann-json3-dev libbenchmark-dev libsqlite3-dev
  python3-matplotlib python3-numpy python3-scipy
  pybind11-dev python3-dev python3-pytest python3-dask python3-distributed
)

# The sanitizer suite and the fuzzers (./tools/test.sh --sanitize, tools/fuzz.sh) build with
# clang and its runtimes (libFuzzer, ASan, UBSan, LSan) into build-sanitize/.
ACCELCAL_SANITIZE_PACKAGES=(clang libclang-rt-14-dev)
ACCELCAL_SANITIZE_SKIPPED='^(Discover\.FalseDiscoveryRateOnNullDataIsAtMostAlpha|OutsideTheCatalogue/HonestVerdictTest\..*|CorrelatedNoise\.ReportedSigmasMatchTheMonteCarloSpread|HeavyTails\.TheRobustFitsSigmasMatchTheMonteCarloSpread|Ambiguity\..*|NullRateStudy\.CountsDoNotDependOnTheThreadCount|ScaleCubic\.DiscoveryNamesItWhenHiddenAndEstimatesItWithinThreeSigma|NullRateStudy\.FalseDiscoveryRateIsWithinAlphaOnTwoDesigns|DeadReckon\.ReportedCovarianceMatchesMonteCarlo.*|MinSamplesBinary\.MonteCarloChecksAgreeWithTheAnalyticCurveWithinBinomialError|AnalyseDesign\.AnalyticCurveAgreesWithFullSimulation|CoverageStudy\.TheBaselinesReportedCovarianceIsRightOnTheCourseScenario|ProgressBinary\.AlwaysShowsTheTimeLeftOnStderrAndChangesNoOutput|TriadMlCalibration\.ReportedSigmaMatchesTheMonteCarloSpread|TriadStudy\..*SigmasMatchTheMonteCarloSpread|TriadStudy\.FailsWhen.*|FerrarisLeastSquares\..*MonteCarlo.*|Installed\..*|EveryEffect/JointEffectRecoveryTest\..*|EveryEffectOfTheCatalogue/HiddenEffectTest\..*/(angleoffset|nonorthogonality|biasdrift[xy]|scalenonlinearity[xy]|runbiasshift[xy]|noisevariance[xy])( .*)?|Discover\.(FindsBothEffectsOfAPair|DropsAnEffectALaterEffectExplains)|CoverageStudy\.AHiddenEffectBiasesWhatItShould|ScaleCubic\.DiscoveryFindsNothingWhenNothingIsHidden|SolveJoint\.CompressedResidualsGiveThePerSampleSolution|SinCos\.AccurateOnFourMillionPointsInPlusMinusFourPi|TriadDiscovery\.NullSessionsAreExplainedAtTheStatedRate|AllanMonteCarlo\..*|RepeatabilityMonteCarlo\..*|TriadPoseNoise\..*|Mimu4444\..*|Discover\.OnTheCourseDataTheBaselineExplainsTheData|MinSamplesBinary\.AnswersTheReportsQuestionOnTheCourseData|AllanFit\.PoseMeanVarianceMatchesTheSpreadOfSimulatedMeans|DiscoveryLandmarkTie\..*|DiscoveryPartners\..*|TwoAxisShapes/HiddenShapeTest\..*|TwoAxisShapes\.NullRateOverMixedDesignsIsAtMostAlpha|TriadShapes\..*|TriadPartners\..*|OutsideTheModel/TriadShapeTest\..*|GyroscopeTurnSampling\..*|GyroscopeEarthRate\..*|GyroscopeTurnShapes\..*|GyroscopeRepeatability\..*)$'
# -O1 and line tables only (what ASan's authors advise): reports keep file:line, and the build
# takes about half the time of -O2 -g.
ACCELCAL_SANITIZE_CMAKE_ARGS=(
  -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -gline-tables-only -DNDEBUG"
  -DCMAKE_CXX_COMPILER=clang++ -DACCELCAL_FUZZ=ON -DACCELCAL_BUILD_BENCHMARKS=OFF
  -DACCELCAL_PYTHON=OFF
)

# accelcal_install_packages [extra packages...]: the project's packages and any extra ones.
accelcal_install_packages() {
  local missing=()
  local package
  for package in "${ACCELCAL_PACKAGES[@]}" "$@"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$package")
    fi
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "accelcal: installing ${missing[*]}" >&2
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  local log
  log=$(mktemp)
  if ! { $sudo apt-get update -qq && $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"; } >"$log" 2>&1; then
    tail -20 "$log" >&2
    echo "accelcal: apt-get install ${missing[*]} failed (log above)" >&2
    rm -f "$log"
    return 1
  fi
  rm -f "$log"
}

# accelcal_build BUILD_DIR [--target NAME]... [extra cmake args...]
# Without --target: everything (the library, the binaries, the tests, the benchmarks).
# With it: only those targets and what they link, as tools/run.sh does. Targets, not cache
# options, so that run.sh and test.sh can share build/ in any order without one of them
# leaving the other a cache that turned its tests off.
accelcal_build() {
  local build_dir=$1
  shift
  local targets=()
  while [ $# -gt 0 ] && [ "$1" = "--target" ]; do
    targets+=("$2")
    shift 2
  done
  local jobs first_build=""
  jobs=$(nproc 2>/dev/null || echo 2)
  [ -e "$build_dir/CMakeCache.txt" ] || first_build=1
  # ccache where present, unless a launcher is already chosen (CMake's environment variable
  # CMAKE_CXX_COMPILER_LAUNCHER, or an argument): a second checkout, or the same one after a
  # pull, compiles only what changed. CCACHE_DISABLE=1 in the environment turns it off.
  local launcher=()
  if [ -z "${CMAKE_CXX_COMPILER_LAUNCHER:-}" ] && command -v ccache >/dev/null 2>&1 &&
    [[ " $* " != *" -DCMAKE_CXX_COMPILER_LAUNCHER="* ]]; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  fi
  cmake -S "$ACCELCAL_ROOT" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "$@" \
    >/dev/null ||
    { echo "accelcal: cmake configure failed (run cmake -S . -B $build_dir to see why)" >&2; return 1; }
  local build_args=(--build "$build_dir" -j "$jobs")
  local what="everything"
  if [ ${#targets[@]} -gt 0 ]; then
    build_args+=(--target "${targets[@]}")
    what="${targets[*]} and the library it links"
  fi
  local note=""
  [ -n "$first_build" ] && note="first build: several minutes; "
  echo "accelcal: building $what in $build_dir (${note}log: $build_dir/build.log)" >&2
  if ! cmake "${build_args[@]}" >"$build_dir/build.log" 2>&1; then
    grep -E -B2 -A6 'error|Error' "$build_dir/build.log" | head -80 >&2
    echo "accelcal: build failed; the full log is $build_dir/build.log" >&2
    return 1
  fi
}

# accelcal_register_python BUILD_DIR: makes the Python module built in BUILD_DIR/python
# (docs/python.md) importable by the system Python, /usr/bin/python3, with one line in a .pth
# file of its site directory: the system-wide one when writable (root), else the user's.
# Idempotent (the file is rewritten, not appended to); the last checkout registered wins. A
# moved or deleted build directory is harmless: Python skips a .pth line naming no folder, and
# the next run of run.sh or test.sh writes the new one. Quiet unless the file changes.
accelcal_register_python() {
  local module_dir
  module_dir=$(cd "$1" && pwd)/python
  # Configured without it (no pybind11, -DACCELCAL_PYTHON=OFF): nothing to register.
  [ -d "$module_dir/CMakeFiles" ] && [ -x /usr/bin/python3 ] || return 0
  /usr/bin/python3 - "$module_dir" <<'PYTHON' || echo "accelcal: could not register the Python module (docs/python.md)" >&2
import os, site, sys
module_dir = sys.argv[1]
line = module_dir + "\n"
# The system-wide site directory (/usr/local/lib/python3.X/dist-packages), else the user's.
targets = [d for d in site.getsitepackages() if d.startswith("/usr/local/")][:1]
targets.append(site.getusersitepackages())
for target in targets:
    pth = os.path.join(target, "accelcal.pth")
    try:
        with open(pth) as f:
            if f.read() == line:
                sys.exit(0)
    except OSError:
        pass
    try:
        os.makedirs(target, exist_ok=True)
        with open(pth + ".tmp", "w") as f:
            f.write(line)
        os.replace(pth + ".tmp", pth)
    except OSError:
        continue
    print(f"accelcal: /usr/bin/python3 imports accelcal from {module_dir} ({pth})",
          file=sys.stderr)
    sys.exit(0)
sys.exit(1)
PYTHON
}

# accelcal_build_python BUILD_DIR: the Python module alone (tools/run.sh builds only what the
# main job links), then its registration; nothing when the build has no module.
accelcal_build_python() {
  local build_dir=$1
  [ -d "$build_dir/python/CMakeFiles" ] || return 0
  if ! cmake --build "$build_dir" -j "$(nproc 2>/dev/null || echo 2)" --target accelcal_python \
    >>"$build_dir/build.log" 2>&1; then
    echo "accelcal: building the Python module failed; the full log is $build_dir/build.log" >&2
    return 1
  fi
  accelcal_register_python "$build_dir"
}
