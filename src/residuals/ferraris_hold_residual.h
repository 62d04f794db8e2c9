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
// the 9 triad parameters and w, with no singularity near the solution. The residual is
// residuals/triad_pose_residual.h's with the direction n = Q^T (+-e_i) given: whitened, so the
// cost is 1/2 chi-square.

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <array>

#include "models/triad.h"
#include "residuals/triad_pose_residual.h"

namespace accelcal {

class FerrarisHoldResidual {
 public:
  // `reference_direction` = Q0^T (+-e_i), a unit vector in the starting frame.
  FerrarisHoldResidual(const std::array<double, 3>& measured_mean,
                       const std::array<double, 3>& mean_stddev,
                       const std::array<double, 3>& reference_direction, double gravity_mps2)
      : pose_(measured_mean, mean_stddev, gravity_mps2),
        reference_direction_(reference_direction) {}

  template <typename T>
  bool operator()(const T* const parameters, const T* const frame_correction, T* residual) const {
    // n = Exp(w)^T Q0^T (+-e_i) = Exp(-w) reference_direction; then the pose's residual with
    // that direction known.
    const T inverse_correction[3] = {-frame_correction[0], -frame_correction[1],
                                     -frame_correction[2]};
    const T reference[3] = {T(reference_direction_[0]), T(reference_direction_[1]),
                            T(reference_direction_[2])};
    T direction[3];
    ceres::AngleAxisRotatePoint(inverse_correction, reference, direction);
    return pose_(parameters, direction, residual);
  }

  static ceres::CostFunction* Create(const std::array<double, 3>& measured_mean,
                                     const std::array<double, 3>& mean_stddev,
                                     const std::array<double, 3>& reference_direction,
                                     double gravity_mps2) {
    return new ceres::AutoDiffCostFunction<FerrarisHoldResidual, 3, kTriadParameterCount, 3>(
        new FerrarisHoldResidual(measured_mean, mean_stddev, reference_direction, gravity_mps2));
  }

 private:
  const TriadPoseResidual pose_;
  const std::array<double, 3> reference_direction_;  // unit vector
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_FERRARIS_HOLD_RESIDUAL_H_
