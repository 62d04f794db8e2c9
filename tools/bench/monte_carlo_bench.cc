// Monte Carlo throughput of the baseline on the course-sized scenario (tp2-2018: a
// 20001-sample tilt test and a 6000-sample run per trial): simulate both, fit the
// baseline, dead-reckon with the exact covariance. Trials/s on 1 and 2 threads.
//
//   build/bin/monte_carlo_bench --benchmark_min_time=2

#include <benchmark/benchmark.h>

#include "estimation/linear_ls.h"
#include "simulation/embedded_scenarios.h"
#include "studies/coverage_study.h"

namespace accelcal {
namespace {

void BM_BaselineCoverageTrials(benchmark::State& state) {
  Scenario scenario;
  if (!LoadDefaultScenario(&scenario).ok()) {
    state.SkipWithError("cannot load the embedded scenario");
    return;
  }
  CoverageOptions options;
  options.trials = 200;
  options.threads = static_cast<int>(state.range(0));
  options.progress = false;
  for (auto _ : state) {
    const CoverageResult result = RunCoverageStudy(scenario, options);
    benchmark::DoNotOptimize(result.parameters[0].mean);
  }
  state.SetItemsProcessed(state.iterations() * options.trials);
  state.counters["threads"] = options.threads;
}
BENCHMARK(BM_BaselineCoverageTrials)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The closed-form baseline alone: samples/s of the one-pass sufficient statistics.
void BM_StreamingBaseline(benchmark::State& state) {
  TiltSchedule schedule;
  schedule.sample_count = static_cast<int>(state.range(0));
  const CalibrationTest test = SimulateTiltTest(schedule, CourseTableOneTruth(), 1);
  LinearLsOptions options;
  options.noise_variance_x = 0.25;
  options.noise_variance_y = 0.64;
  for (auto _ : state) {
    BaselineFit fit;
    benchmark::DoNotOptimize(EstimateLinearLs(test, options, &fit).ok());
    benchmark::DoNotOptimize(fit.parameters[0]);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_StreamingBaseline)->Arg(20001)->Arg(1000000)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace accelcal

BENCHMARK_MAIN();
