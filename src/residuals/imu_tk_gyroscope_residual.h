#ifndef ACCELCAL_RESIDUALS_IMU_TK_GYROSCOPE_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_IMU_TK_GYROSCOPE_RESIDUAL_H_

// imu_tk's residual of one turn of the gyroscope's calibration (Tedaldi, Pretto, Menegatti, ICRA
// 2014, eq. 13-14; imu_tk's MultiPosGyroResidual), reimplemented:
//
//   r = R(theta)^T g_before - g_after          (3 components, dimensionless)
//
// g_before, g_after: the unit gravity directions (the normalised mean calibrated specific
// force) of two consecutive static intervals, in the accelerometer's frame; R: the rotation
// obtained by integrating the gyroscope's angular rate w_j = T K (u_j - b) (models/gyroscope.h)
// over the turn's samples with imu_tk's RK4 rule (IntegrateAngularRate), the body's attitude at
// the end in its frame at the start. A vector fixed in the world, seen from the body, turns by
// R^T: a perfect gyroscope brings g_before onto g_after and r = 0. R^T g is imu_tk's
// `rot_mat.transpose() * g_versor_pos0` (older versions wrote `.inverse()`, the same rotation).
//
// Like imu_tk's accelerometer residual (residuals/imu_tk_residual.h) it is deliberately not
// whitened: it is imu_tk's cost as imu_tk states it, so that its printed final cost is
// reproduced. The offset b is fixed (imu_tk's default and its Xsens example: the mean of the
// initial rest), so the parameter block is the 9 angles and gains.

#include <ceres/autodiff_cost_function.h>
#include <ceres/cost_function.h>

#include <array>
#include <utility>
#include <vector>

#include "models/gyroscope.h"

namespace accelcal {

class ImuTkGyroscopeResidual {
 public:
  // `raw`: the gyroscope's outputs over the turn (counts), in order; `step_s[j]`: the time from
  // raw[j] to raw[j + 1] (s); `offset`: b (counts); the gravity directions: unit vectors.
  ImuTkGyroscopeResidual(const std::array<double, 3>& gravity_before,
                         const std::array<double, 3>& gravity_after,
                         std::vector<std::array<double, 3>> raw, std::vector<double> step_s,
                         const GyroscopeOffset& offset)
      : gravity_before_(gravity_before),
        gravity_after_(gravity_after),
        raw_(std::move(raw)),
        step_s_(std::move(step_s)),
        offset_(offset) {}

  template <typename T>
  bool operator()(const T* const parameters, T* residual) const {
    const T offset[3] = {T(offset_[0]), T(offset_[1]), T(offset_[2])};
    T rotation[9];
    IntegrateAngularRate(
        static_cast<int>(raw_.size()),
        [&](int j, T* rate) { GyroscopeAngularRate(parameters, offset, raw_[j].data(), rate); },
        step_s_, rotation);
    for (int k = 0; k < 3; ++k) {
      residual[k] = rotation[k] * gravity_before_[0] + rotation[3 + k] * gravity_before_[1] +
                    rotation[6 + k] * gravity_before_[2] - gravity_after_[k];
    }
    return true;
  }

  static ceres::CostFunction* Create(const std::array<double, 3>& gravity_before,
                                     const std::array<double, 3>& gravity_after,
                                     std::vector<std::array<double, 3>> raw,
                                     std::vector<double> step_s, const GyroscopeOffset& offset) {
    return new ceres::AutoDiffCostFunction<ImuTkGyroscopeResidual, 3, kGyroscopeParameterCount>(
        new ImuTkGyroscopeResidual(gravity_before, gravity_after, std::move(raw), std::move(step_s),
                                   offset));
  }

 private:
  const std::array<double, 3> gravity_before_;
  const std::array<double, 3> gravity_after_;
  const std::vector<std::array<double, 3>> raw_;
  const std::vector<double> step_s_;
  const GyroscopeOffset offset_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_IMU_TK_GYROSCOPE_RESIDUAL_H_
