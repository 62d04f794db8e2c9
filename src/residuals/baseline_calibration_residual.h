#ifndef ACCELCAL_RESIDUALS_BASELINE_CALIBRATION_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_BASELINE_CALIBRATION_RESIDUAL_H_

// Whitened residual of one tilt-test sample on one axis under the baseline model:
//
//   r_i = (m_k,i - (f_k(theta_i) + b_k + s_k f_k(theta_i))) / sigma_k
//
// with f_k from models/tilt_table.h and the terms of the two baseline effects
// (models/effects/bias.h, models/effects/scale.h). Dividing
// by the stated sigma_k makes the cost a chi-square, so ceres::Covariance returns the
// parameter covariance in the spec's units.
//
// The baseline has no angle offset, so f_k is a constant of the sample and is
// evaluated once, in double, in the constructor; the Jet evaluation is then two
// multiply-adds.

#include <ceres/autodiff_cost_function.h>

#include "models/effects/bias.h"
#include "models/effects/scale.h"
#include "models/tilt_table.h"

namespace accelcal {

class BaselineCalibrationResidual {
 public:
  BaselineCalibrationResidual(double theta_rad, double measured_mps2, SensingAxis axis,
                              double gravity_mps2, double noise_stddev_mps2)
      : measured_mps2_(measured_mps2),
        specific_force_mps2_(SpecificForceAlong(theta_rad, axis, gravity_mps2)),
        sqrt_information_(1.0 / noise_stddev_mps2) {}

  template <typename T>
  bool operator()(const T* const bias, const T* const scale, T* residual) const {
    AxisPolynomial<T> response;
    Bias::AddAxisTerms(bias[0], 0.0, &response);
    Scale::AddAxisTerms(scale[0], 0.0, &response);
    const T predicted = response.c[1] * specific_force_mps2_ + response.c[0];
    residual[0] = (T(measured_mps2_) - predicted) * sqrt_information_;
    return true;
  }

  static ceres::CostFunction* Create(double theta_rad, double measured_mps2, SensingAxis axis,
                                     double gravity_mps2, double noise_stddev_mps2) {
    return new ceres::AutoDiffCostFunction<BaselineCalibrationResidual, 1, 1, 1>(
        new BaselineCalibrationResidual(theta_rad, measured_mps2, axis, gravity_mps2,
                                        noise_stddev_mps2));
  }

 private:
  static double SpecificForceAlong(double theta_rad, SensingAxis axis, double gravity_mps2) {
    double force_x;
    double force_y;
    TiltTableSpecificForce(theta_rad, gravity_mps2, &force_x, &force_y);
    return axis == SensingAxis::kX ? force_x : force_y;
  }

  const double measured_mps2_;
  const double specific_force_mps2_;
  const double sqrt_information_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_BASELINE_CALIBRATION_RESIDUAL_H_
