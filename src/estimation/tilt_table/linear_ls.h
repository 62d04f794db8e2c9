#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_LINEAR_LS_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_LINEAR_LS_H_

// The reference report's linear baseline in closed form. Per axis k, with the tilt
// table's specific force f_k(theta_i) (models/tilt_table.h) and y_i = m_k,i - f_k,i,
//
//   y_i = b_k + s_k f_k,i + zeta_i,      zeta_i ~ N(0, sigma_k^2), sigma_k^2 known,
//
// so the weighted least-squares estimate is ordinary least squares per axis and its
// covariance is sigma_k^2 (A^T A)^-1. The axes share no parameter and no noise, so the
// 4x4 covariance is block diagonal.
//
// The estimate is computed from streaming sufficient statistics, CalibrationAccumulator
// (estimation/tilt_table/linear_ls_accumulator.h): one pass over the samples, constant memory in N,
// mergeable across chunks.

#include <string>

#include "common/measurements.h"
#include "common/status.h"
#include "estimation/tilt_table/baseline_parameters.h"
#include "estimation/tilt_table/linear_ls_accumulator.h"

namespace accelcal {

struct LinearLsOptions {
  double gravity_mps2 = 9.8;
  double noise_variance_x = 0.0;  // stated sigma_x^2, (m/s^2)^2
  double noise_variance_y = 0.0;  // stated sigma_y^2, (m/s^2)^2
  // Bias and scale of an axis "cannot be separated" when the variance of the bias
  // estimate is inflated by more than this factor by its correlation with the scale
  // (VIF = 1 / (1 - rho^2)); 1e6 means |rho| > 0.9999995.
  double max_variance_inflation = 1e6;
};

// The options of a fit under the run's stated noise variances and gravity `gravity_mps2`
// (the one place they are copied from RunConditions).
inline LinearLsOptions LinearLsOptionsFor(const RunConditions& conditions, double gravity_mps2) {
  LinearLsOptions options;
  options.gravity_mps2 = gravity_mps2;
  options.noise_variance_x = conditions.noise_variance_x;
  options.noise_variance_y = conditions.noise_variance_y;
  return options;
}

// Validates the options (positive finite variances and gravity) and the design
// (at least 3 samples; every axis's bias and scale separable), then solves.
Status SolveLinearLs(const CalibrationAccumulator& statistics, const LinearLsOptions& options,
                     BaselineFit* fit);

// One pass over `test`, then SolveLinearLs.
Status EstimateLinearLs(const CalibrationTest& test, const LinearLsOptions& options,
                        BaselineFit* fit);

// The fit when no noise variance is stated: each axis's variance estimated from its residuals,
// s_k^2 = RSS_k / (N - 2) (a unit-variance fit's chi-square is its RSS), then the fit under
// them. `options`' variances are ignored and set to the estimates. The covariance is then
// right for white noise, but the chi-square is N - 2 by construction and checks nothing.
Status EstimateLinearLsWithNoiseFromResiduals(const CalibrationTest& test, LinearLsOptions* options,
                                              BaselineFit* fit);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_LINEAR_LS_H_
