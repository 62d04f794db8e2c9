#ifndef ACCELCAL_RESIDUALS_FERRARIS_HOLD_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_FERRARIS_HOLD_RESIDUAL_H_

// One hold of a Ferraris session under Ferraris's own assumption, made explicit: the specific
// force of hold "axis i up" is +g e_i, of "axis i down" -g e_i, in an orthogonal frame the
// holds define (imucal's frame). In accelcal's frame (models/imucal_convention.h, a = Q a')
// that is a' = Q^T (+-g e_i), and the triad outputs u = b + K^-1 T^-1 a' (TriadRawOutput):
//
//   r_k = (ubar_k - u_k) / sigma_k,   Q = Q0 Exp(w)        (k = x, y, z)
//
// ubar: the hold's mean (counts); sigma_k = sqrt(s_k^2 / N): the standard deviation of a mean
// of N samples of white noise of variance s_k^2; Q0 a fixed starting rotation (the closed
// form's) and w its small correction (rad, angle-axis, a block of 3), so the 12 unknowns are
// the 9 triad parameters and w, with no singularity near the solution. Whitened, so the cost
// is 1/2 chi-square.

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <array>

#include "models/triad.h"

namespace accelcal {

class FerrarisHoldResidual {
 public:
  // `reference_force` = Q0^T (+-g e_i), m/s^2 in the starting frame.
  FerrarisHoldResidual(const std::array<double, 3>& measured_mean,
                       const std::array<double, 3>& mean_stddev,
                       const std::array<double, 3>& reference_force)
      : measured_mean_(measured_mean),
        mean_stddev_(mean_stddev),
        reference_force_(reference_force) {}

  template <typename T>
  bool operator()(const T* const parameters, const T* const frame_correction, T* residual) const {
    // a' = Exp(w)^T Q0^T (+-g e_i) = Exp(-w) reference_force.
    const T inverse_correction[3] = {-frame_correction[0], -frame_correction[1],
                                     -frame_correction[2]};
    const T reference[3] = {T(reference_force_[0]), T(reference_force_[1]), T(reference_force_[2])};
    T force[3];
    ceres::AngleAxisRotatePoint(inverse_correction, reference, force);
    T predicted[3];
    TriadRawOutput(parameters, force, predicted);
    for (int k = 0; k < 3; ++k) {
      residual[k] = (T(measured_mean_[k]) - predicted[k]) / T(mean_stddev_[k]);
    }
    return true;
  }

  static ceres::CostFunction* Create(const std::array<double, 3>& measured_mean,
                                     const std::array<double, 3>& mean_stddev,
                                     const std::array<double, 3>& reference_force) {
    return new ceres::AutoDiffCostFunction<FerrarisHoldResidual, 3, kTriadParameterCount, 3>(
        new FerrarisHoldResidual(measured_mean, mean_stddev, reference_force));
  }

 private:
  const std::array<double, 3> measured_mean_;    // counts
  const std::array<double, 3> mean_stddev_;      // counts
  const std::array<double, 3> reference_force_;  // m/s^2
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_FERRARIS_HOLD_RESIDUAL_H_
