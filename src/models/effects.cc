#include "models/effects.h"

namespace accelcal {

const std::array<ParameterInfo, kParameterCount>& ParameterCatalogue() {
  static const std::array<ParameterInfo, kParameterCount> catalogue = {{
      {Parameter::kBiasX, "bias_x", "m/s^2", "constant bias of the x axis", true, 0.0, 0.0},
      {Parameter::kScaleX, "scale_x", "1", "scale-factor error of the x axis", true, 0.0, 0.0},
      {Parameter::kBiasY, "bias_y", "m/s^2", "constant bias of the y axis", true, 0.0, 0.0},
      {Parameter::kScaleY, "scale_y", "1", "scale-factor error of the y axis", true, 0.0, 0.0},
      {Parameter::kAngleOffset, "angle_offset", "rad",
       "table zero offset: theta_true = theta_reported + delta (calibration test only)", false, 0.0,
       0.004},
      {Parameter::kNonorthogonality, "nonorthogonality", "rad", "y sensing axis tilted toward x",
       false, 0.0, 0.004},
      {Parameter::kBiasDriftX, "bias_drift_x", "m/s^2",
       "x bias change from the first to the last calibration sample", false, 0.0, 0.1},
      {Parameter::kBiasDriftY, "bias_drift_y", "m/s^2",
       "y bias change from the first to the last calibration sample", false, 0.0, 0.1},
      {Parameter::kScaleNonlinearityX, "scale_nonlinearity_x", "1/(m/s^2)",
       "second-order scale term of the x axis", false, 0.0, 0.001},
      {Parameter::kScaleNonlinearityY, "scale_nonlinearity_y", "1/(m/s^2)",
       "second-order scale term of the y axis", false, 0.0, 0.001},
      {Parameter::kRunBiasShiftX, "run_bias_shift_x", "m/s^2",
       "x bias in the vehicle run minus bias in the calibration test", false, 0.0, 0.02},
      {Parameter::kRunBiasShiftY, "run_bias_shift_y", "m/s^2",
       "y bias in the vehicle run minus bias in the calibration test", false, 0.0, 0.02},
      {Parameter::kNoiseVarianceX, "noise_variance_x", "1",
       "ratio of the true x noise variance to the stated one", false, 1.0, 2.0},
      {Parameter::kNoiseVarianceY, "noise_variance_y", "1",
       "ratio of the true y noise variance to the stated one", false, 1.0, 2.0},
  }};
  return catalogue;
}

const ParameterInfo* FindParameter(const std::string& name) {
  for (const ParameterInfo& info : ParameterCatalogue()) {
    if (name == info.name) return &info;
  }
  return nullptr;
}

const ParameterInfo& Info(Parameter parameter) {
  return ParameterCatalogue()[static_cast<int>(parameter)];
}

}  // namespace accelcal
