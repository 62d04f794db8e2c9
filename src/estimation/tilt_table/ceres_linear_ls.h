#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_CERES_LINEAR_LS_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_CERES_LINEAR_LS_H_

// The linear baseline posed as a Ceres problem: one whitened residual per sample and
// axis (residuals/baseline_calibration_residual.h), four named scalar parameter blocks
// (bias_x, scale_x, bias_y, scale_y), covariance from ceres::Covariance. It must agree
// with the closed form (estimation/tilt_table/linear_ls.h) to 1e-9; it exists as the baseline that
// the joint nonlinear problem extends, and as a check on both.

#include <string>

#include "common/measurements.h"
#include "common/status.h"
#include "estimation/solver/solver_report.h"
#include "estimation/tilt_table/baseline_parameters.h"
#include "estimation/tilt_table/linear_ls.h"

namespace accelcal {

struct CeresLinearLsOptions {
  LinearLsOptions model;  // g and the stated noise variances, as for the closed form
  int max_iterations = 50;
  int num_threads = 1;
};

struct CeresLinearLsResult {
  BaselineFit fit;
  SolverReport solver;
};

// Validates like EstimateLinearLs (same messages for the same bad input), solves, and
// computes the covariance. Fails when the solver does not converge or the covariance
// cannot be computed, naming the reason.
Status EstimateLinearLsWithCeres(const CalibrationTest& test, const CeresLinearLsOptions& options,
                                 CeresLinearLsResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_CERES_LINEAR_LS_H_
