#include "studies/coverage_study.h"

#include <Eigen/Dense>
#include <cmath>

#include "estimation/tilt_table/linear_ls.h"
#include "estimation/tilt_table/trajectory.h"
#include "simulation/monte_carlo.h"

namespace accelcal {
namespace {

// Two-sided normal quantiles and chi-square(2) quantiles of kCoverageLevels.
constexpr std::array<double, 3> kNormalQuantile = {0.994457883209753, 1.959963984540054,
                                                   2.575829303548901};
double ChiSquare2Quantile(double level) { return -2.0 * std::log(1.0 - level); }

struct Trial {
  bool ok = false;
  Eigen::Vector4d estimate;
  Eigen::Matrix4d covariance;
  Eigen::Vector2d chi2_per_dof;
  Eigen::Vector2d endpoint_error;
  Eigen::Matrix2d endpoint_covariance;
};

}  // namespace

CoverageResult RunCoverageStudy(const Scenario& scenario, const CoverageOptions& options) {
  const ModelParameters<double>& truth_parameters = scenario.truth.parameters;
  Eigen::Vector4d truth;
  for (const Parameter parameter : kBaselineParameters) {
    truth[BaselineIndex(parameter)] = truth_parameters[parameter];
  }
  std::vector<Trial> trials(options.trials);
  ProgressCounter progress(options.progress, options.trials);
  MonteCarloOptions monte_carlo;
  monte_carlo.trials = options.trials;
  monte_carlo.threads = options.threads;
  monte_carlo.progress = &progress;
  const MonteCarloTiming timing = RunTrials(monte_carlo, [&](int index) {
    const SimulatedData data = SimulateScenario(scenario, options.seed, index);
    const LinearLsOptions fit_options =
        LinearLsOptionsFor(data.conditions, scenario.truth.gravity_mps2);
    BaselineFit fit;
    Trial& trial = trials[index];
    if (!EstimateLinearLs(data.test, fit_options, &fit).ok()) return;
    TrajectoryOptions trajectory_options;
    trajectory_options.path_stride = data.run.size();  // the endpoint is all we need
    DeadReckoningResult trajectory;
    if (!DeadReckon(data.run, data.conditions, fit, trajectory_options, &trajectory).ok()) return;
    trial.ok = true;
    trial.estimate = fit.parameters;
    trial.covariance = fit.covariance;
    trial.chi2_per_dof =
        Eigen::Vector2d(fit.chi2_x.chi2 / fit.chi2_x.dof, fit.chi2_y.chi2 / fit.chi2_y.dof);
    trial.endpoint_error = trajectory.endpoint - data.true_endpoint;
    trial.endpoint_covariance = trajectory.covariance;
  });

  CoverageResult result;
  result.seconds = timing.seconds;
  result.threads = timing.threads;
  std::vector<const Trial*> good;
  for (const Trial& trial : trials) {
    if (trial.ok) good.push_back(&trial);
  }
  result.trials = static_cast<int>(good.size());
  result.failed_trials = options.trials - result.trials;
  if (good.empty()) return result;
  const double n = static_cast<double>(good.size());
  Eigen::Vector2d endpoint_mean = Eigen::Vector2d::Zero();
  Eigen::Vector2d endpoint_reported_variance = Eigen::Vector2d::Zero();
  for (const Trial* trial : good) {
    result.mean_chi2_per_dof += trial->chi2_per_dof / n;
    endpoint_mean += trial->endpoint_error / n;
    endpoint_reported_variance += trial->endpoint_covariance.diagonal() / n;
    for (int level = 0; level < 3; ++level) {
      const double radius2 = ChiSquare2Quantile(kCoverageLevels[level]);
      const Eigen::Vector2d e = trial->endpoint_error;
      result.endpoint_ellipse_coverage[level] +=
          (e.dot(trial->endpoint_covariance.ldlt().solve(e)) <= radius2) / n;
      for (int axis = 0; axis < 2; ++axis) {
        const int b = BaselineIndex(BiasOf(axis));
        const int s = BaselineIndex(ScaleOf(axis));
        const Eigen::Vector2d d(trial->estimate[b] - truth[b], trial->estimate[s] - truth[s]);
        Eigen::Matrix2d c;
        c << trial->covariance(b, b), trial->covariance(b, s), trial->covariance(s, b),
            trial->covariance(s, s);
        result.axis_ellipse_coverage[axis][level] += (d.dot(c.ldlt().solve(d)) <= radius2) / n;
      }
    }
  }
  Eigen::Vector2d endpoint_variance = Eigen::Vector2d::Zero();
  for (const Trial* trial : good) {
    endpoint_variance += (trial->endpoint_error - endpoint_mean).cwiseAbs2() / std::max(1.0, n - 1);
  }
  result.endpoint_bias_sigma = endpoint_mean.cwiseQuotient(endpoint_reported_variance.cwiseSqrt());
  result.endpoint_sd_ratio =
      endpoint_variance.cwiseSqrt().cwiseQuotient(endpoint_reported_variance.cwiseSqrt());
  for (int i = 0; i < kBaselineParameterCount; ++i) {
    ParameterCoverage& row = result.parameters[i];
    row.truth = truth[i];
    double variance = 0.0;
    for (const Trial* trial : good) {
      row.mean += trial->estimate[i] / n;
      row.reported_sd += std::sqrt(trial->covariance(i, i)) / n;
    }
    for (const Trial* trial : good) {
      variance += std::pow(trial->estimate[i] - row.mean, 2) / std::max(1.0, n - 1);
      for (int level = 0; level < 3; ++level) {
        row.interval_coverage[level] +=
            (std::abs(trial->estimate[i] - truth[i]) <=
             kNormalQuantile[level] * std::sqrt(trial->covariance(i, i))) /
            n;
      }
    }
    row.empirical_sd = std::sqrt(variance);
    row.bias_sigma = (row.mean - row.truth) / row.reported_sd;
  }
  return result;
}

int EffectImpactRows() {
  int rows = 0;
  for (const ParameterInfo& info : ParameterCatalogue()) rows += info.baseline ? 0 : 1;
  return rows;
}

std::vector<EffectImpact> RunEffectImpactTable(const Scenario& scenario,
                                               const CoverageOptions& options) {
  std::vector<EffectImpact> table;
  const int64_t total = static_cast<int64_t>(EffectImpactRows()) * options.trials;
  for (const ParameterInfo& info : ParameterCatalogue()) {
    if (info.baseline) continue;
    Scenario hidden = scenario;
    hidden.truth.parameters[info.parameter] = info.example_size;
    EffectImpact row;
    row.effect = info.parameter;
    row.size = info.example_size;
    CoverageOptions row_options = options;
    row_options.progress =
        ProgressPart(options.progress, static_cast<int64_t>(table.size()) * options.trials, total);
    row.result = RunCoverageStudy(hidden, row_options);
    table.push_back(row);
  }
  return table;
}

}  // namespace accelcal
