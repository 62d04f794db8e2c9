#ifndef ACCELCAL_RESIDUALS_IMU_TK_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_IMU_TK_RESIDUAL_H_

// imu_tk's residual of one static sample of a triad (Tedaldi, Pretto, Menegatti, ICRA 2014):
//
//   r_i = g - |T K (u_i - b)|        (m/s^2; models/triad.h)
//
// At rest the specific force is gravity, whose magnitude g is known and whose direction is
// not; the residual compares magnitudes only, so no direction per pose is estimated.
// It is deliberately not whitened: it is imu_tk's cost as imu_tk states it, unweighted, so
// that its printed final cost is reproduced. (A maximum-likelihood residual would divide by
// the noise of |a|, and its cost would then be a chi-square.)

#include <ceres/autodiff_cost_function.h>

#include <array>
#include <cmath>

#include "models/triad.h"

namespace accelcal {

class ImuTkResidual {
 public:
  ImuTkResidual(const std::array<double, 3>& raw, double gravity_mps2)
      : raw_(raw), gravity_mps2_(gravity_mps2) {}

  template <typename T>
  bool operator()(const T* const parameters, T* residual) const {
    T specific_force[3];
    TriadSpecificForce(parameters, raw_.data(), specific_force);
    using std::sqrt;
    residual[0] = T(gravity_mps2_) - sqrt(specific_force[0] * specific_force[0] +
                                          specific_force[1] * specific_force[1] +
                                          specific_force[2] * specific_force[2]);
    return true;
  }

  static ceres::CostFunction* Create(const std::array<double, 3>& raw, double gravity_mps2) {
    return new ceres::AutoDiffCostFunction<ImuTkResidual, 1, kTriadParameterCount>(
        new ImuTkResidual(raw, gravity_mps2));
  }

 private:
  const std::array<double, 3> raw_;
  const double gravity_mps2_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_IMU_TK_RESIDUAL_H_
