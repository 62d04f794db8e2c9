#ifndef ACCELCAL_STUDIES_COVERAGE_STUDY_H_
#define ACCELCAL_STUDIES_COVERAGE_STUDY_H_

// Is the reported uncertainty right? K simulated experiments of a scenario, each fitted
// by the linear baseline and dead-reckoned: the empirical spread of the estimates
// against the reported covariance, the coverage of 68/95/99% intervals (per parameter)
// and ellipses (bias and scale of each axis; the endpoint), and chi-square per axis.
//
// The effect table repeats the study with one effect of the catalogue hidden in the data
// (at its example size) but left out of the model, to show what each does to the
// baseline: which estimates it biases and by how many sigma, and what happens to
// chi-square and coverage.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "common/progress.h"
#include "estimation/tilt_table/baseline_parameters.h"
#include "models/effects.h"
#include "simulation/scenario.h"

namespace accelcal {

struct CoverageOptions {
  int trials = 1000;
  uint64_t seed = 1;
  int threads = 0;      // 0: all cores
  ProgressFn progress;  // per finished trial, of `trials` (of the table's, in the table)
};

constexpr std::array<double, 3> kCoverageLevels = {0.68, 0.95, 0.99};

struct ParameterCoverage {
  double truth = 0.0;
  double mean = 0.0;
  double empirical_sd = 0.0;
  double reported_sd = 0.0;                   // mean over trials of the reported sigma
  double bias_sigma = 0.0;                    // (mean - truth) / reported_sd
  std::array<double, 3> interval_coverage{};  // at kCoverageLevels
};

struct CoverageResult {
  int trials = 0;
  int failed_trials = 0;  // fits refused (cannot happen with a sane scenario)
  std::array<ParameterCoverage, kBaselineParameterCount> parameters;  // at BaselineIndex
  std::array<std::array<double, 3>, 2> axis_ellipse_coverage{};       // (bias, scale) of x and y
  std::array<double, 3> endpoint_ellipse_coverage{};
  Eigen::Vector2d endpoint_bias_sigma = Eigen::Vector2d::Zero();  // mean error / reported sigma
  Eigen::Vector2d endpoint_sd_ratio = Eigen::Vector2d::Zero();    // empirical / reported sigma
  Eigen::Vector2d mean_chi2_per_dof = Eigen::Vector2d::Zero();
  double seconds = 0.0;
  int threads = 1;
};

CoverageResult RunCoverageStudy(const Scenario& scenario, const CoverageOptions& options);

struct EffectImpact {
  Parameter effect;
  double size = 0.0;
  CoverageResult result;
};

// One row per non-baseline effect, each hidden at its example size, each of options.trials.
int EffectImpactRows();
std::vector<EffectImpact> RunEffectImpactTable(const Scenario& scenario,
                                               const CoverageOptions& options);

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_COVERAGE_STUDY_H_
