// Monte Carlo throughput of the baseline on the course-sized scenario (tp2-2018: a
// 20001-sample tilt test and a 6000-sample run per trial): simulate both, fit the
// baseline, dead-reckon with the exact covariance. Trials/s on 1 and 2 threads. Then the
// closed-form baseline alone (BM_StreamingBaseline) and its sine and cosine (BM_SinCos).
//
//   build/bin/monte_carlo_bench --benchmark_min_time=2
//   build/bin/monte_carlo_bench --benchmark_filter='Streaming|SinCos' --benchmark_min_time=1

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstddef>
#include <vector>

#include "common/sincos.h"
#include "estimation/tilt_table/linear_ls.h"
#include "io/scenario_json.h"
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

// What the baseline spends most of its time on: the sine and cosine of every angle, by the
// batch kernel (common/sincos.h) and by std::sin + std::cos. Nanoseconds per element:
// the reported time divided by the argument, or 1 / items_per_second.
std::vector<double> CourseLikeAngles(int count) {
  std::vector<double> theta_rad(count);
  for (int i = 0; i < count; ++i) theta_rad[i] = 2.0 * 3.14159265358979323846 * i / (count - 1);
  return theta_rad;
}

template <void (*kSinCos)(const double*, std::size_t, double*, double*)>
void BM_SinCos(benchmark::State& state) {
  const std::vector<double> theta_rad = CourseLikeAngles(static_cast<int>(state.range(0)));
  std::vector<double> sin_theta(theta_rad.size());
  std::vector<double> cos_theta(theta_rad.size());
  for (auto _ : state) {
    kSinCos(theta_rad.data(), theta_rad.size(), sin_theta.data(), cos_theta.data());
    benchmark::DoNotOptimize(sin_theta.data());
    benchmark::DoNotOptimize(cos_theta.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void StdSinCos(const double* x, std::size_t n, double* sin_out, double* cos_out) {
  for (std::size_t i = 0; i < n; ++i) {
    sin_out[i] = std::sin(x[i]);
    cos_out[i] = std::cos(x[i]);
  }
}

BENCHMARK_TEMPLATE(BM_SinCos, SinCos)->Name("BM_SinCos/kernel")->Arg(512)->Arg(20001);
BENCHMARK_TEMPLATE(BM_SinCos, sincos_internal::SinCosBaseline)
    ->Name("BM_SinCos/kernel_sse2")
    ->Arg(512)
    ->Arg(20001);
BENCHMARK_TEMPLATE(BM_SinCos, StdSinCos)->Name("BM_SinCos/std")->Arg(512)->Arg(20001);

}  // namespace
}  // namespace accelcal

BENCHMARK_MAIN();
