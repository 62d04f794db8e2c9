#ifndef ACCELCAL_RESIDUALS_ENDPOINT_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_ENDPOINT_RESIDUAL_H_

// The run tied to a landmark: the dead-reckoned endpoint as a function of the parameters
// that act in the run, minus the landmark, whitened by the endpoint's own noise
// covariance (the run's integrated white noise, plus the landmark's position uncertainty):
//
//   p_end(theta) = p0 + v0 T + sum_j w_j a_j(theta),   a_j = RunCorrection(theta)(m_j)
//   r = L^-1 (p_end(theta) - landmark),                 L L^T = Sigma_noise + sigma_L^2 I
//
// Parameters: RunParameters() (models/effects.h), one scalar block each; with the built-in
// effects bias_x, scale_x, bias_y, scale_y, nonorthogonality, scale_nonlinearity_x,
// scale_nonlinearity_y, run_bias_shift_x, run_bias_shift_y. An effect registered later
// that acts in the run becomes a block here without a change to this file.
//
// Why it is fast: the trapezoidal double integration is linear in the accelerations, so
// the endpoint is one weighted sum with weights w_j computed once (models/dead_reckoning.h)
// instead of a recursion that keeps velocities. An evaluation is a single pass over the
// M samples with two accumulators, no allocation, and a Jet of fixed size (one dual part
// per block); each sample costs two InvertAxisResponse calls. The projection is linear by
// contract (models/effect.h), so it is undone once on the two sums rather than per sample,
// keeping sin and cos of a Jet out of the loop.
//
// When every run term of degree 2 or more in the force is held at its neutral zero
// (`linear_inverse`, see InverseIsAffine), the inverse is affine in the measurement,
// f(m) = f(0) + (f(1) - f(0)) m, so the weighted sum needs only sum_j w_j and
// sum_j w_j m_j, taken once: an evaluation no longer depends on M. The two values f(0),
// f(1) come from InvertAxisResponse itself, so the model stays in one place.

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <vector>

#include "models/dead_reckoning.h"
#include "models/sensor_model.h"
#include "residuals/scalar_blocks.h"

namespace accelcal {

class EndpointResidual {
 public:
  static constexpr int kBlockCount = kRunParameterCount;

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

  template <typename T, typename... Rest>
  bool operator()(const T* const first, Rest... rest) const {
    ModelParameters<T> parameters;
    T* residual = GatherParameters(kBlocks, &parameters, first, rest...);
    const RunCorrection<T> correction(parameters);
    T sum_along_x(0.0);
    T sum_along_y(0.0);
    if (linear_inverse_) {
      for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
        const AxisPolynomial<T>& response = correction.response(axis);
        if (!(response.c[2] == T(0.0) && response.c[3] == T(0.0))) return false;
      }
      const T zero_x = correction.AlongAxis(T(0.0), SensingAxis::kX);
      const T zero_y = correction.AlongAxis(T(0.0), SensingAxis::kY);
      sum_along_x = sum_weights_ * zero_x +
                    weighted_sum_x_ * (correction.AlongAxis(T(1.0), SensingAxis::kX) - zero_x);
      sum_along_y = sum_weights_ * zero_y +
                    weighted_sum_y_ * (correction.AlongAxis(T(1.0), SensingAxis::kY) - zero_y);
    } else {
      for (size_t j = 0; j < weights_.size(); ++j) {
        sum_along_x += weights_[j] * correction.AlongAxis(T(measured_x_[j]), SensingAxis::kX);
        sum_along_y += weights_[j] * correction.AlongAxis(T(measured_y_[j]), SensingAxis::kY);
      }
    }
    T sum_x;
    T sum_y;
    correction.Unproject(sum_along_x, sum_along_y, &sum_x, &sum_y);
    const T dx = sum_x + offset_.x();
    const T dy = sum_y + offset_.y();
    residual[0] = sqrt_information_(0, 0) * dx + sqrt_information_(0, 1) * dy;
    residual[1] = sqrt_information_(1, 0) * dx + sqrt_information_(1, 1) * dy;
    return true;
  }

  // Whether the run's inverse stays affine in the measurement while the parameters `free`
  // move from `values`: every run term of degree 2 or more in the force is held, at its
  // neutral value (where its term vanishes).
  static bool InverseIsAffine(const ModelParameters<double>& values,
                              const std::vector<Parameter>& free) {
    for (const Parameter parameter : kBlocks) {
      if (EffectOf(parameter).force_degree < 2) continue;
      if (values[parameter] != EffectOf(parameter).neutral) return false;
      if (std::find(free.begin(), free.end(), parameter) != free.end()) return false;
    }
    return true;
  }

  // The parameter blocks, in the order Create's cost function takes them.
  static constexpr const std::array<Parameter, kBlockCount>& kBlocks = RunParameters();

  static ceres::CostFunction* Create(EndpointResidual* residual) {
    return new ScalarBlocksCostFunction<EndpointResidual, 2, kBlockCount>(residual);
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
