#ifndef ACCELCAL_RESIDUALS_TRIAD_POSE_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_TRIAD_POSE_RESIDUAL_H_

// The maximum-likelihood residual of one static pose of a triad (docs/triad.md):
//
//   r_p,k = (ubar_p,k - u_p,k) / sigma_p,k,    u_p = b + K^-1 T^-1 g n_p     (k = x, y, z)
//
// ubar_p: the mean of the pose's N_p samples (counts); u_p: what the triad outputs under the
// specific force g n_p (TriadRawOutput, models/triad.h), n_p the pose's unknown unit gravity
// direction (its own parameter block, kept on the unit sphere by a manifold);
// sigma_p,k = sqrt(s_k^2 / N_p): the standard deviation of a mean of N_p samples of white
// noise of variance s_k^2 (counts). Whitened here, so the cost is 1/2 chi-square and
// ceres::Covariance is the inverse information.
//
// With effects beyond the 9 parameters (models/triad_effect_list.h: second-order scale terms,
// offset drift, ...), u_p is TriadPredictOutput's and their coefficients are a third block of
// kTriadEffectCoefficientCount doubles (CreateWithEffects; the calibration holds the ones it
// does not estimate at zero). Create keeps the 9-parameter problem as it was.

#include <ceres/autodiff_cost_function.h>

#include <array>

#include "models/triad_effect_list.h"

namespace accelcal {

class TriadPoseResidual {
 public:
  TriadPoseResidual(const std::array<double, 3>& measured_mean,
                    const std::array<double, 3>& mean_stddev, double gravity_mps2,
                    const TriadPoseContext& context = TriadPoseContext())
      : measured_mean_(measured_mean),
        mean_stddev_(mean_stddev),
        gravity_mps2_(gravity_mps2),
        context_(context) {}

  // Blocks: the 9 triad parameters, the unit direction n_p.
  template <typename T>
  bool operator()(const T* const parameters, const T* const direction, T* residual) const {
    return Evaluate(parameters, static_cast<const T*>(nullptr), direction, residual);
  }

  // Blocks: the 9 triad parameters, the effects' coefficients, the unit direction n_p.
  template <typename T>
  bool operator()(const T* const parameters, const T* const effects, const T* const direction,
                  T* residual) const {
    return Evaluate(parameters, effects, direction, residual);
  }

  static ceres::CostFunction* Create(const std::array<double, 3>& measured_mean,
                                     const std::array<double, 3>& mean_stddev,
                                     double gravity_mps2) {
    return new ceres::AutoDiffCostFunction<TriadPoseResidual, 3, kTriadParameterCount, 3>(
        new TriadPoseResidual(measured_mean, mean_stddev, gravity_mps2));
  }

  static ceres::CostFunction* CreateWithEffects(const std::array<double, 3>& measured_mean,
                                                const std::array<double, 3>& mean_stddev,
                                                double gravity_mps2,
                                                const TriadPoseContext& context) {
    return new ceres::AutoDiffCostFunction<TriadPoseResidual, 3, kTriadParameterCount,
                                           kTriadEffectCoefficientCount, 3>(
        new TriadPoseResidual(measured_mean, mean_stddev, gravity_mps2, context));
  }

 private:
  template <typename T>
  bool Evaluate(const T* parameters, const T* effects, const T* direction, T* residual) const {
    T predicted[3];
    if (!TriadPredictOutput(parameters, effects, context_, direction, gravity_mps2_, predicted))
      return false;
    for (int k = 0; k < 3; ++k) {
      residual[k] = (T(measured_mean_[k]) - predicted[k]) / T(mean_stddev_[k]);
    }
    return true;
  }

  const std::array<double, 3> measured_mean_;
  const std::array<double, 3> mean_stddev_;  // counts
  const double gravity_mps2_;
  const TriadPoseContext context_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_TRIAD_POSE_RESIDUAL_H_
