// Discovery end to end on course-sized data (the tp2-2018 scenario: 20001 tilt samples,
// a 6000-sample run, four landmarks): nothing hidden, and an angle offset hidden at
// about 9 sigma (one forward step, a refit, cross-validation).
//
//   build/bin/discover_bench --benchmark_min_time=2

#include <benchmark/benchmark.h>

#include "estimation/tilt_table/discovery.h"
#include "io/scenario_json.h"

namespace accelcal {
namespace {

void BM_Discover(benchmark::State& state, const std::string& hidden) {
  Scenario scenario;
  if (!LoadDefaultScenario(&scenario).ok() || !ApplyScenarioOverrides(hidden, &scenario).ok()) {
    state.SkipWithError("scenario");
    return;
  }
  const SimulatedData data = SimulateScenario(scenario, 1);
  for (auto _ : state) {
    DiscoveryResult result;
    if (!Discover(data.test, data.run, data.conditions, data.landmarks, DiscoveryOptions(), &result)
             .ok()) {
      state.SkipWithError("discover failed");
      break;
    }
    benchmark::DoNotOptimize(result.effects.size());
  }
}
BENCHMARK_CAPTURE(BM_Discover, nothing_hidden, std::string(""))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Discover, angle_offset_hidden, std::string("angle_offset=0.004"))
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace accelcal

BENCHMARK_MAIN();
