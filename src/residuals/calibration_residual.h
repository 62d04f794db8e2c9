#ifndef ACCELCAL_RESIDUALS_CALIBRATION_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_CALIBRATION_RESIDUAL_H_

// Whitened residual of one tilt-test sample on one axis under the spec's full model:
//
//   r_i = (m_k,i - AxisOutput(f_along_k(theta_i + delta, eps); b_k, s_k, k2_k, d_k u_i)) / sigma_k
//
// (models/tilt_table.h, models/sensor_model.h). Parameters, each a scalar block in the
// spec's units: bias_k, scale_k, scale_nonlinearity_k, bias_drift_k, angle_offset,
// nonorthogonality. The x axis does not depend on nonorthogonality (x is the reference
// axis); the block is passed anyway so both axes share one functor.

#include <ceres/autodiff_cost_function.h>

#include "models/sensor_model.h"
#include "models/tilt_table.h"
#include "residuals/baseline_calibration_residual.h"

namespace accelcal {

class CalibrationResidual {
 public:
  CalibrationResidual(double theta_rad, double measured_mps2, SensingAxis axis,
                      double drift_coordinate, double gravity_mps2, double noise_stddev_mps2)
      : theta_rad_(theta_rad),
        measured_mps2_(measured_mps2),
        axis_(axis),
        drift_coordinate_(drift_coordinate),
        gravity_mps2_(gravity_mps2),
        sqrt_information_(1.0 / noise_stddev_mps2) {}

  // The model's prediction of one axis's output at (theta, u): the one expression both
  // this per-sample residual and CompressedCalibrationResidual evaluate.
  template <typename T>
  static T Predict(double theta_rad, double drift_coordinate, SensingAxis axis, double gravity_mps2,
                   const T& bias, const T& scale, const T& scale_nonlinearity, const T& bias_drift,
                   const T& angle_offset, const T& nonorthogonality) {
    T force_x;
    T force_y;
    TiltTableSpecificForce(T(theta_rad), angle_offset, gravity_mps2, &force_x, &force_y);
    T along_x;
    T along_y;
    ProjectOnSensingAxes(force_x, force_y, nonorthogonality, &along_x, &along_y);
    AxisErrors<T> errors;
    errors.bias = bias;
    errors.scale = scale;
    errors.scale_nonlinearity = scale_nonlinearity;
    errors.bias_drift = bias_drift;
    return AxisOutput(axis == SensingAxis::kX ? along_x : along_y, errors, drift_coordinate,
                      Phase::kCalibrationTest);
  }

  template <typename T>
  bool operator()(const T* const bias, const T* const scale, const T* const scale_nonlinearity,
                  const T* const bias_drift, const T* const angle_offset,
                  const T* const nonorthogonality, T* residual) const {
    const T predicted =
        Predict(theta_rad_, drift_coordinate_, axis_, gravity_mps2_, bias[0], scale[0],
                scale_nonlinearity[0], bias_drift[0], angle_offset[0], nonorthogonality[0]);
    residual[0] = (T(measured_mps2_) - predicted) * sqrt_information_;
    return true;
  }

  static ceres::CostFunction* Create(double theta_rad, double measured_mps2, SensingAxis axis,
                                     double drift_coordinate, double gravity_mps2,
                                     double noise_stddev_mps2) {
    return new ceres::AutoDiffCostFunction<CalibrationResidual, 1, 1, 1, 1, 1, 1, 1>(
        new CalibrationResidual(theta_rad, measured_mps2, axis, drift_coordinate, gravity_mps2,
                                noise_stddev_mps2));
  }

 private:
  const double theta_rad_;
  const double measured_mps2_;
  const SensingAxis axis_;
  const double drift_coordinate_;
  const double gravity_mps2_;
  const double sqrt_information_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_CALIBRATION_RESIDUAL_H_
