#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_TRAJECTORY_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_TRAJECTORY_H_

// Dead reckoning of the vehicle run with the baseline's estimates, and the endpoint's
// covariance, exact for the linear-Gaussian case. It has two independent parts:
//
//   parameter part  J Sigma_params J^T, J = d p_end / d (estimated parameters), computed
//                   exactly by running the same trapezoidal recursion in ceres::Jet over
//                   the nine parameters that act in the run (bias, scale, quadratic term
//                   and run bias shift of each axis, and the non-orthogonality); the
//                   calibration-only parameters (angle offset, drift) have zero columns;
//   noise part      the run's own noise through the integration, white
//                   (sum_j w_j^2 sigma_k^2 / (1 + s_k)^2 per axis) or AR(1) with the
//                   estimate's noise_correlation (models/noise_model.h), which no
//                   calibration can shrink (exact for the baseline; with a quadratic term,
//                   the first-order value at zero acceleration).
//
// Along the path the noise part is propagated as the covariance of (p, v, a_prev):
// a_j enters two consecutive trapezoidal steps, so the previous acceleration's noise
// is part of the state. That is O(M) and exact at every sample.

#include <Eigen/Core>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"
#include "estimation/tilt_table/baseline_parameters.h"
#include "estimation/tilt_table/parameter_estimate.h"

namespace accelcal {

struct TrajectoryOptions {
  // Keep every path_stride-th sample in the path series (the last is always kept).
  int path_stride = 10;
};

struct PathPoint {
  double timestamp_s = 0.0;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();              // corrected, m
  Eigen::Vector2d raw_position = Eigen::Vector2d::Zero();          // raw outputs integrated, m
  Eigen::Matrix2d parameter_covariance = Eigen::Matrix2d::Zero();  // m^2
  Eigen::Matrix2d noise_covariance = Eigen::Matrix2d::Zero();      // m^2
};

struct DeadReckoningResult {
  Eigen::Vector2d endpoint = Eigen::Vector2d::Zero();      // corrected, m
  Eigen::Vector2d raw_endpoint = Eigen::Vector2d::Zero();  // uncorrected, m
  Eigen::Vector2d end_velocity = Eigen::Vector2d::Zero();  // corrected, m/s
  // d endpoint / d (the estimate's free parameters, in its order), in m per unit.
  Eigen::Matrix<double, 2, Eigen::Dynamic> jacobian;
  std::vector<Parameter> jacobian_columns;
  // The column of `parameter` in `jacobian`, or -1 when it does not act in the run.
  int JacobianColumn(Parameter parameter) const {
    for (size_t i = 0; i < jacobian_columns.size(); ++i) {
      if (jacobian_columns[i] == parameter) return static_cast<int>(i);
    }
    return -1;
  }
  Eigen::Matrix2d parameter_part = Eigen::Matrix2d::Zero();  // m^2
  Eigen::Matrix2d noise_part = Eigen::Matrix2d::Zero();      // m^2
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();      // sum of the two, m^2
  double dt_s = 0.0;
  double duration_s = 0.0;  // t_last - t_first
  int sample_count = 0;
  std::vector<PathPoint> path;
};

// Corrects every run sample with the estimate (inverting the sensor model), integrates
// from the initial conditions, and propagates both covariance parts. The noise part
// uses the stated variances of `conditions` times the estimate's noise_variance ratios.
Status DeadReckon(const VehicleRun& run, const RunConditions& conditions,
                  const ParameterEstimate& estimate, const TrajectoryOptions& options,
                  DeadReckoningResult* result);

// The same for the baseline fit (its columns are bias_x, scale_x, bias_y, scale_y).
Status DeadReckon(const VehicleRun& run, const RunConditions& conditions, const BaselineFit& fit,
                  const TrajectoryOptions& options, DeadReckoningResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_TRAJECTORY_H_
