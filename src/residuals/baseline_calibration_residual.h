#ifndef ACCELCAL_RESIDUALS_BASELINE_CALIBRATION_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_BASELINE_CALIBRATION_RESIDUAL_H_

// Whitened residual of one tilt-test sample on one axis under the baseline model:
//
//   r_i = (m_k,i - AxisOutput(f_k(theta_i); b_k, s_k)) / sigma_k
//
// with f_k from models/tilt_table.h and AxisOutput from models/sensor_model.h. Dividing
// by the stated sigma_k makes the cost a chi-square, so ceres::Covariance returns the
// parameter covariance in the spec's units.
//
// The baseline has no angle offset, so f_k is a constant of the sample and is
// evaluated once, in double, in the constructor; the Jet evaluation is then two
// multiply-adds.

#include <ceres/autodiff_cost_function.h>

#include "models/sensor_model.h"
#include "models/tilt_table.h"

namespace accelcal {

enum class SensingAxis { kX, kY };

class BaselineCalibrationResidual {
 public:
  BaselineCalibrationResidual(double theta_rad, double measured_mps2, SensingAxis axis,
                              double gravity_mps2, double noise_stddev_mps2)
      : measured_mps2_(measured_mps2),
        specific_force_mps2_(SpecificForceAlong(theta_rad, axis, gravity_mps2)),
        sqrt_information_(1.0 / noise_stddev_mps2) {}

  template <typename T>
  bool operator()(const T* const bias, const T* const scale, T* residual) const {
    AxisErrors<T> errors;
    errors.bias = bias[0];
    errors.scale = scale[0];
    const T predicted = AxisOutput(T(specific_force_mps2_), errors, 0.0, Phase::kCalibrationTest);
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
    TiltTableSpecificForce(theta_rad, 0.0, gravity_mps2, &force_x, &force_y);
    return axis == SensingAxis::kX ? force_x : force_y;
  }

  const double measured_mps2_;
  const double specific_force_mps2_;
  const double sqrt_information_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_BASELINE_CALIBRATION_RESIDUAL_H_
