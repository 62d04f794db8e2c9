// Links the installed library, its headers included by the accelcal/ prefix: simulate the
// course's setting, fit the baseline, print bias_x.
#include <cstdio>

#include "accelcal/estimation/tilt_table/linear_ls.h"
#include "accelcal/io/scenario_json.h"

int main() {
  accelcal::Scenario scenario;
  if (!accelcal::LoadDefaultScenario(&scenario).ok()) return 1;
  const accelcal::SimulatedData data = accelcal::SimulateScenario(scenario, 1);
  accelcal::LinearLsOptions options;
  options.noise_variance_x = data.conditions.noise_variance_x;
  options.noise_variance_y = data.conditions.noise_variance_y;
  accelcal::BaselineFit fit;
  if (!accelcal::EstimateLinearLs(data.test, options, &fit).ok()) return 1;
  std::printf("bias_x %.5f\n", fit.Value(accelcal::Parameter::kBiasX));
  return 0;
}
