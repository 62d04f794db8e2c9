#!/usr/bin/env bash
# Shared set-up for tools/run.sh and tools/test.sh: install the Debian packages that are
# missing (quiet when all are present), then configure and build in Release into build/.
# Sourced, not executed.

ACCELCAL_PACKAGES=(
  build-essential cmake pkg-config
  libceres-dev libeigen3-dev libgflags-dev libgoogle-glog-dev
  libgtest-dev libgmock-dev libmatio-dev zlib1g-dev nlohmann-json3-dev libbenchmark-dev libsqlite3-dev
  python3-matplotlib python3-numpy python3-scipy
)

# The sanitizer suite and the fuzzers (./tools/test.sh --sanitize, tools/fuzz.sh) build with
# clang and its runtimes (libFuzzer, ASan, UBSan, LSan) into build-sanitize/.
ACCELCAL_SANITIZE_PACKAGES=(clang libclang-rt-14-dev)
ACCELCAL_SANITIZE_SKIPPED='^(Discover\.FalseDiscoveryRateOnNullDataIsAtMostAlpha|OutsideTheCatalogue/HonestVerdictTest\..*|CorrelatedNoise\.ReportedSigmasMatchTheMonteCarloSpread|HeavyTails\.TheRobustFitsSigmasMatchTheMonteCarloSpread|Ambiguity\..*|NullRateStudy\.CountsDoNotDependOnTheThreadCount|ScaleCubic\.DiscoveryNamesItWhenHiddenAndEstimatesItWithinThreeSigma|NullRateStudy\.FalseDiscoveryRateIsWithinAlphaOnTwoDesigns|DeadReckon\.ReportedCovarianceMatchesMonteCarlo.*|MinSamplesBinary\.MonteCarloChecksAgreeWithTheAnalyticCurveWithinBinomialError|AnalyseDesign\.AnalyticCurveAgreesWithFullSimulation|CoverageStudy\.TheBaselinesReportedCovarianceIsRightOnTheCourseScenario|ProgressBinary\.AlwaysShowsTheTimeLeftOnStderrAndChangesNoOutput|TriadMlCalibration\.ReportedSigmaMatchesTheMonteCarloSpread|TriadStudy\..*SigmasMatchTheMonteCarloSpread|TriadStudy\.FailsWhen.*|FerrarisLeastSquares\..*MonteCarlo.*|Installed\..*|EveryEffect/JointEffectRecoveryTest\..*|EveryEffectOfTheCatalogue/HiddenEffectTest\..*/(angleoffset|nonorthogonality|biasdrift[xy]|scalenonlinearity[xy]|runbiasshift[xy]|noisevariance[xy])( .*)?|Discover\.(FindsBothEffectsOfAPair|DropsAnEffectALaterEffectExplains)|CoverageStudy\.AHiddenEffectBiasesWhatItShould|ScaleCubic\.DiscoveryFindsNothingWhenNothingIsHidden|SolveJoint\.CompressedResidualsGiveThePerSampleSolution|SinCos\.AccurateOnFourMillionPointsInPlusMinusFourPi|TriadDiscovery\.NullSessionsAreExplainedAtTheStatedRate|AllanMonteCarlo\..*|RepeatabilityMonteCarlo\..*|TriadPoseNoise\..*|Mimu4444\..*|Discover\.OnTheCourseDataTheBaselineExplainsTheData|MinSamplesBinary\.AnswersTheReportsQuestionOnTheCourseData|AllanFit\.PoseMeanVarianceMatchesTheSpreadOfSimulatedMeans)$'
# -O1 and line tables only (what ASan's authors advise): reports keep file:line, and the build
# takes about half the time of -O2 -g.
ACCELCAL_SANITIZE_CMAKE_ARGS=(
  -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -gline-tables-only -DNDEBUG"
  -DCMAKE_CXX_COMPILER=clang++ -DACCELCAL_FUZZ=ON -DACCELCAL_BUILD_BENCHMARKS=OFF
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
  cmake -S "$ACCELCAL_ROOT" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null ||
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
