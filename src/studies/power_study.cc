#include "studies/power_study.h"

#include <cmath>

#include "estimation/tilt_table/discovery.h"
#include "estimation/tilt_table/joint_estimator.h"
#include "simulation/monte_carlo.h"

namespace accelcal {
namespace {

// The effect's sigma on this design: a joint fit with the effect free on a null dataset
// (the noise ratios: the von Neumann estimator's sd).
double EffectSigma(const Scenario& scenario, Parameter effect, uint64_t seed) {
  const SimulatedData data = SimulateScenario(scenario, seed, 1u << 30);
  if (IsNoiseRatio(effect)) {
    const double n = data.test.size();
    return std::sqrt(8.0 * (n - 1) + 4.0 * (n - 2)) / (2.0 * (n - 1));
  }
  JointOptions options;
  options.effects = {effect};
  options.gravity_mps2 = scenario.truth.gravity_mps2;
  options.noise_variance_x = data.conditions.noise_variance_x;
  options.noise_variance_y = data.conditions.noise_variance_y;
  options.landmark_mode = JointOptions::Landmark::kNamed;
  options.landmark_name = data.reached_landmark;
  JointResult result;
  if (!SolveJoint(data.test, data.run, data.conditions, data.landmarks, options, &result).ok())
    return 0.0;
  return result.estimate.StandardDeviation(effect);
}

}  // namespace

int64_t PowerStudyTrials(const PowerOptions& options) {
  int64_t effects = 0;
  for (const ParameterInfo& info : ParameterCatalogue()) effects += info.baseline ? 0 : 1;
  return effects * static_cast<int64_t>(options.sizes_sigma.size()) * options.trials;
}

std::vector<PowerRow> RunPowerStudy(const Scenario& base, const PowerOptions& options) {
  std::vector<PowerRow> table;
  ProgressCounter progress(options.progress, PowerStudyTrials(options));
  for (const ParameterInfo& info : ParameterCatalogue()) {
    if (info.baseline) continue;
    Scenario scenario = base;
    if (ActsOnlyInRun(info.parameter)) {
      scenario.landmarks = LandmarkSpec();
      scenario.landmarks.decoys = true;
      scenario.landmarks.decoy_min_distance_m = 400.0;
    }
    PowerRow row;
    row.effect = info.parameter;
    row.sigma = EffectSigma(scenario, info.parameter, options.seed);
    for (const double size : options.sizes_sigma) {
      Scenario hidden = scenario;
      hidden.truth.parameters[info.parameter] = info.neutral + size * row.sigma;
      std::vector<int> named(options.trials, 0);
      std::vector<int> others(options.trials, 0);
      MonteCarloOptions monte_carlo;
      monte_carlo.trials = options.trials;
      monte_carlo.threads = options.threads;
      monte_carlo.progress = &progress;
      RunTrials(monte_carlo, [&](int trial) {
        const SimulatedData data = SimulateScenario(hidden, options.seed, trial);
        DiscoveryOptions discovery;
        discovery.alpha = options.alpha;
        discovery.gravity_mps2 = hidden.truth.gravity_mps2;
        discovery.cross_validation_folds = 0;
        DiscoveryResult result;
        if (!Discover(data.test, data.run, data.conditions, data.landmarks, discovery, &result)
                 .ok())
          return;
        for (const DiscoveredEffect& effect : result.effects) {
          if (effect.effect == info.parameter) {
            named[trial] = 1;
          } else {
            others[trial] = 1;
          }
        }
      });
      double named_sum = 0.0;
      double others_sum = 0.0;
      for (int t = 0; t < options.trials; ++t) {
        named_sum += named[t];
        others_sum += others[t];
      }
      row.detection.push_back(named_sum / options.trials);
      row.other_effects.push_back(others_sum / options.trials);
    }
    table.push_back(row);
  }
  return table;
}

}  // namespace accelcal
