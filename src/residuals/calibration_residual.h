#ifndef ACCELCAL_RESIDUALS_CALIBRATION_RESIDUAL_H_
#define ACCELCAL_RESIDUALS_CALIBRATION_RESIDUAL_H_

// Whitened residual of one tilt-test sample on one axis under the full model:
//
//   r_i = (m_k,i - PredictCalibrationOutput(theta_i, u_i; p)) / sigma_k
//
// (models/sensor_model.h: the true table angle, the table's force, its projection on the
// sensing axes and the axis's output, each from the registered effects' terms). Its
// parameters are CalibrationParameters(axis) (models/effects.h), one scalar block each in
// the spec's units: with the built-in effects bias_k, scale_k, angle_offset,
// nonorthogonality, bias_drift_k, scale_nonlinearity_k. An effect registered later that
// acts in the tilt test becomes a block here without a change to this file.

#include <array>

#include "models/sensor_model.h"
#include "residuals/scalar_blocks.h"

namespace accelcal {

class CalibrationResidual {
 public:
  static constexpr int kBlockCount = kCalibrationParameterCount;

  CalibrationResidual(double theta_rad, double measured_mps2, SensingAxis axis,
                      double drift_coordinate, double gravity_mps2, double noise_stddev_mps2)
      : theta_rad_(theta_rad),
        measured_mps2_(measured_mps2),
        axis_(axis),
        drift_coordinate_(drift_coordinate),
        gravity_mps2_(gravity_mps2),
        sqrt_information_(1.0 / noise_stddev_mps2),
        blocks_(Blocks(axis)) {}

  template <typename T, typename... Rest>
  bool operator()(const T* const first, Rest... rest) const {
    ModelParameters<T> parameters;
    T* residual = GatherParameters(blocks_, &parameters, first, rest...);
    const T predicted =
        PredictCalibrationOutput(theta_rad_, drift_coordinate_, axis_, gravity_mps2_, parameters);
    residual[0] = (T(measured_mps2_) - predicted) * sqrt_information_;
    return true;
  }

  // The parameter blocks, in the order Create's cost function takes them.
  static const std::array<Parameter, kBlockCount>& Blocks(SensingAxis axis) {
    return CalibrationParameters(axis);
  }

  static ceres::CostFunction* Create(double theta_rad, double measured_mps2, SensingAxis axis,
                                     double drift_coordinate, double gravity_mps2,
                                     double noise_stddev_mps2) {
    return new ScalarBlocksCostFunction<CalibrationResidual, 1, kBlockCount>(
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
  const std::array<Parameter, kBlockCount>& blocks_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_CALIBRATION_RESIDUAL_H_
