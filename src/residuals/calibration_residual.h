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
//
// With time-correlated noise (models/noise_model.h) the residual is the whitened one,
//
//   w_i = current (m_i - prediction_i) - previous (m_{i-1} - prediction_{i-1}),
//
// so the block also holds the previous sample (CreateWhitened).

#include <array>

#include "models/sensor_model.h"
#include "residuals/scalar_blocks.h"

namespace accelcal {

class CalibrationResidual {
 public:
  static constexpr int kBlockCount = kCalibrationParameterCount;

  // One sample of the test.
  struct Sample {
    double theta_rad = 0.0;
    double measured_mps2 = 0.0;
    double drift_coordinate = 0.0;
  };

  CalibrationResidual(const Sample& sample, const Sample& previous, SensingAxis axis,
                      double gravity_mps2, double current_weight, double previous_weight)
      : sample_(sample),
        previous_(previous),
        axis_(axis),
        gravity_mps2_(gravity_mps2),
        current_weight_(current_weight),
        previous_weight_(previous_weight),
        blocks_(Blocks(axis)) {}

  template <typename T, typename... Rest>
  bool operator()(const T* const first, Rest... rest) const {
    ModelParameters<T> parameters;
    T* residual = GatherParameters(blocks_, &parameters, first, rest...);
    residual[0] = current_weight_ * Error(sample_, parameters);
    if (previous_weight_ != 0.0) residual[0] -= previous_weight_ * Error(previous_, parameters);
    return true;
  }

  // The parameter blocks, in the order Create's cost function takes them.
  static const std::array<Parameter, kBlockCount>& Blocks(SensingAxis axis) {
    return CalibrationParameters(axis);
  }

  // White noise of standard deviation noise_stddev_mps2.
  static ceres::CostFunction* Create(double theta_rad, double measured_mps2, SensingAxis axis,
                                     double drift_coordinate, double gravity_mps2,
                                     double noise_stddev_mps2) {
    return CreateWhitened({theta_rad, measured_mps2, drift_coordinate}, Sample(), axis,
                          gravity_mps2, 1.0 / noise_stddev_mps2, 0.0);
  }

  // current_weight e(sample) - previous_weight e(previous), e = measured - prediction.
  static ceres::CostFunction* CreateWhitened(const Sample& sample, const Sample& previous,
                                             SensingAxis axis, double gravity_mps2,
                                             double current_weight, double previous_weight) {
    return new ScalarBlocksCostFunction<CalibrationResidual, 1, kBlockCount>(
        new CalibrationResidual(sample, previous, axis, gravity_mps2, current_weight,
                                previous_weight));
  }

 private:
  template <typename T>
  T Error(const Sample& sample, const ModelParameters<T>& parameters) const {
    return T(sample.measured_mps2) - PredictCalibrationOutput(sample.theta_rad,
                                                              sample.drift_coordinate, axis_,
                                                              gravity_mps2_, parameters);
  }

  const Sample sample_;
  const Sample previous_;
  const SensingAxis axis_;
  const double gravity_mps2_;
  const double current_weight_;
  const double previous_weight_;
  const std::array<Parameter, kBlockCount>& blocks_;
};

}  // namespace accelcal

#endif  // ACCELCAL_RESIDUALS_CALIBRATION_RESIDUAL_H_
