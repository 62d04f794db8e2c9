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
#include <ceres/cost_function.h>

#include <array>
#include <cmath>
#include <utility>
#include <vector>

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

// The same residual for many samples in one block, with its Jacobian written out: imu_tk's
// sweep solves nine problems of some 3,800 samples, and one autodiff block per sample made
// Ceres' per-block bookkeeping (evaluation, problem construction) most of its time (issue 20,
// docs/performance.md). ImuTkResidual stays the reference the Jacobian is tested against.
//
// With d = u - b, s = K d, a = T s, e = a / |a|, the residual's partial derivatives are
//   angles:  dr/d yz = e_x s_y,  dr/d zy = -e_x s_z,  dr/d zx = e_y s_z
//   gains:   dr/d k_j = -c_j d_j,  offsets: dr/d b_j = c_j k_j,   with c = T^T e
// (c is the gradient of |a| with respect to s).
class ImuTkBatchResidual : public ceres::CostFunction {
 public:
  // `raw`: the outputs of the samples, one residual each.
  ImuTkBatchResidual(std::vector<std::array<double, 3>> raw, double gravity_mps2)
      : raw_(std::move(raw)), gravity_mps2_(gravity_mps2) {
    set_num_residuals(static_cast<int>(raw_.size()));
    mutable_parameter_block_sizes()->push_back(kTriadParameterCount);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* p = parameters[0];
    const double yz = p[kTriadMisalignmentYz];
    const double zy = p[kTriadMisalignmentZy];
    const double zx = p[kTriadMisalignmentZx];
    double* jacobian = jacobians != nullptr ? jacobians[0] : nullptr;
    for (size_t i = 0; i < raw_.size(); ++i) {
      double a[3];
      TriadSpecificForce(p, raw_[i].data(), a);
      const double norm = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
      residuals[i] = gravity_mps2_ - norm;
      if (jacobian == nullptr) continue;
      const double d[3] = {raw_[i][0] - p[kTriadOffsetX], raw_[i][1] - p[kTriadOffsetY],
                           raw_[i][2] - p[kTriadOffsetZ]};
      const double s[3] = {p[kTriadGainX] * d[0], p[kTriadGainY] * d[1], p[kTriadGainZ] * d[2]};
      const double e[3] = {a[0] / norm, a[1] / norm, a[2] / norm};
      const double c[3] = {e[0], e[1] - yz * e[0], e[2] + zy * e[0] - zx * e[1]};
      double* row = jacobian + i * kTriadParameterCount;
      row[kTriadMisalignmentYz] = e[0] * s[1];
      row[kTriadMisalignmentZy] = -e[0] * s[2];
      row[kTriadMisalignmentZx] = e[1] * s[2];
      for (int j = 0; j < 3; ++j) {
        row[kTriadGainX + j] = -c[j] * d[j];
        row[kTriadOffsetX + j] = c[j] * p[kTriadGainX + j];
      }
    }
    return true;
  }

 private:
  const std::vector<std::array<double, 3>> raw_;
  const double gravity_mps2_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_IMU_TK_RESIDUAL_H_
