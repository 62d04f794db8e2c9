#ifndef ACCELCAL_RESIDUALS_ENDPOINT_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_ENDPOINT_RESIDUAL_H_

// The run tied to a landmark: the dead-reckoned endpoint as a function of the parameters
// that act in the run, minus the landmark, whitened by the endpoint's own noise
// covariance (the run's integrated white noise, plus the landmark's position uncertainty):
//
//   p_end(theta) = p0 + v0 T + sum_j w_j a_j(theta),   a_j = CorrectRunSample(m_j; theta)
//   r = L^-1 (p_end(theta) - landmark),                 L L^T = Sigma_noise + sigma_L^2 I
//
// Parameters (scalar blocks): bias_x, scale_x, scale_nonlinearity_x, run_bias_shift_x,
// bias_y, scale_y, scale_nonlinearity_y, run_bias_shift_y, nonorthogonality.
//
// Why it is fast: the trapezoidal double integration is linear in the accelerations, so
// the endpoint is one weighted sum with weights w_j computed once (models/dead_reckoning.h)
// instead of a recursion that keeps velocities. An evaluation is a single pass over the
// M samples with two accumulators, no allocation, and a Jet of fixed size 9; each sample
// costs two InvertAxisOutput calls. The non-orthogonal projection is linear too, so it is
// undone once on the two sums (UndoProjection) rather than per sample, keeping sin and
// cos of a Jet out of the loop.
//
// With both scale_nonlinearity blocks held at zero (`linear_inverse`), InvertAxisOutput is
// affine in the measurement, f(m) = f(0) + (f(1) - f(0)) m, so the weighted sum needs only
// sum_j w_j and sum_j w_j m_j, taken once: an evaluation no longer depends on M. The two
// values f(0), f(1) come from InvertAxisOutput itself, so the model stays in one place.

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <vector>

#include "models/dead_reckoning.h"
#include "models/sensor_model.h"

namespace accelcal {

class EndpointResidual {
 public:
  // `noise_covariance` is the endpoint's covariance from the run's noise (m^2), e.g. the
  // noise part of DeadReckon; `landmark_sigma_m` the landmark's position uncertainty.
  EndpointResidual(std::vector<double> measured_x, std::vector<double> measured_y, double dt_s,
                   const Eigen::Vector2d& initial_position_m,
                   const Eigen::Vector2d& initial_velocity_mps, const Eigen::Vector2d& landmark_m,
                   const Eigen::Matrix2d& noise_covariance, double landmark_sigma_m,
                   bool linear_inverse = false)
      : measured_x_(std::move(measured_x)),
        measured_y_(std::move(measured_y)),
        weights_(EndpointWeights(static_cast<int>(measured_x_.size()), dt_s)),
        offset_(initial_position_m + initial_velocity_mps * dt_s * (measured_x_.size() - 1) -
                landmark_m) {
    const Eigen::Matrix2d covariance =
        noise_covariance + landmark_sigma_m * landmark_sigma_m * Eigen::Matrix2d::Identity();
    const Eigen::Matrix2d lower = covariance.llt().matrixL();
    sqrt_information_ = lower.inverse();
    linear_inverse_ = linear_inverse;
    for (size_t j = 0; j < weights_.size(); ++j) {
      sum_weights_ += weights_[j];
      weighted_sum_x_ += weights_[j] * measured_x_[j];
      weighted_sum_y_ += weights_[j] * measured_y_[j];
    }
  }

  template <typename T>
  bool operator()(const T* const bias_x, const T* const scale_x, const T* const nonlinearity_x,
                  const T* const shift_x, const T* const bias_y, const T* const scale_y,
                  const T* const nonlinearity_y, const T* const shift_y,
                  const T* const nonorthogonality, T* residual) const {
    AxisErrors<T> x;
    x.bias = bias_x[0];
    x.scale = scale_x[0];
    x.scale_nonlinearity = nonlinearity_x[0];
    x.run_bias_shift = shift_x[0];
    AxisErrors<T> y;
    y.bias = bias_y[0];
    y.scale = scale_y[0];
    y.scale_nonlinearity = nonlinearity_y[0];
    y.run_bias_shift = shift_y[0];
    T sum_along_x(0.0);
    T sum_along_y(0.0);
    if (linear_inverse_) {
      if (!(x.scale_nonlinearity == T(0.0) && y.scale_nonlinearity == T(0.0))) return false;
      const T zero_x = InvertAxisOutput(T(0.0), x);
      const T zero_y = InvertAxisOutput(T(0.0), y);
      sum_along_x =
          sum_weights_ * zero_x + weighted_sum_x_ * (InvertAxisOutput(T(1.0), x) - zero_x);
      sum_along_y =
          sum_weights_ * zero_y + weighted_sum_y_ * (InvertAxisOutput(T(1.0), y) - zero_y);
    } else {
      for (size_t j = 0; j < weights_.size(); ++j) {
        sum_along_x += weights_[j] * InvertAxisOutput(T(measured_x_[j]), x);
        sum_along_y += weights_[j] * InvertAxisOutput(T(measured_y_[j]), y);
      }
    }
    T sum_x;
    T sum_y;
    UndoProjection(sum_along_x, sum_along_y, nonorthogonality[0], &sum_x, &sum_y);
    const T dx = sum_x + offset_.x();
    const T dy = sum_y + offset_.y();
    residual[0] = sqrt_information_(0, 0) * dx + sqrt_information_(0, 1) * dy;
    residual[1] = sqrt_information_(1, 0) * dx + sqrt_information_(1, 1) * dy;
    return true;
  }

  static ceres::CostFunction* Create(EndpointResidual* residual) {
    return new ceres::AutoDiffCostFunction<EndpointResidual, 2, 1, 1, 1, 1, 1, 1, 1, 1, 1>(
        residual);
  }

 private:
  const std::vector<double> measured_x_;
  const std::vector<double> measured_y_;
  const std::vector<double> weights_;
  const Eigen::Vector2d offset_;  // p0 + v0 T - landmark
  Eigen::Matrix2d sqrt_information_;
  bool linear_inverse_ = false;
  double sum_weights_ = 0.0;     // sum_j w_j
  double weighted_sum_x_ = 0.0;  // sum_j w_j m_x,j
  double weighted_sum_y_ = 0.0;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_ENDPOINT_RESIDUAL_H_
