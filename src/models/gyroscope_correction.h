#ifndef ACCELCAL_MODELS_GYROSCOPE_CORRECTION_H_
#define ACCELCAL_MODELS_GYROSCOPE_CORRECTION_H_

// A gyroscope's calibration as a correction applies it: the 9 parameters and the offset
// (models/gyroscope.h) and the effect coefficients (models/gyroscope_effects.h) of the model
// discovery settled on. The rate is GyroscopeCorrectedRate's, w = T v' - G f, in the correction's
// direction already; f is the specific force the calibrated accelerometer measures at the same
// sample (the g-sensitivity's term). Every gyroscope effect is a property of the sensor, so every
// coefficient a calibration carries is applied.

#include <Eigen/Core>
#include <vector>

#include "models/gyroscope.h"
#include "models/gyroscope_effects.h"
#include "models/gyroscope_units.h"

namespace accelcal {

struct GyroscopeCalibrationModel {
  GyroscopeParameters parameters{};
  GyroscopeOffset offset{};
  GyroscopeEffectCoefficients effects{};  // 0 for those the calibration does not carry
  std::vector<int> effects_in_file;       // indices into the block, in its order
  // (kGyroscopeCalibrationParameterCount + kGyroscopeEffectCoefficientCount) square: the 9, the
  // offset, then the block; rows and columns of coefficients not carried are 0.
  Eigen::MatrixXd covariance;
  GyroscopeOutputUnit unit = GyroscopeOutputUnit::kCount;

  bool has_effects() const { return !effects_in_file.empty(); }
  // Whether the correction needs the specific force (a g-sensitivity is carried).
  bool needs_specific_force() const {
    for (const int c : effects_in_file)
      if (c < kGyroscopeScaleAsymmetry) return true;
    return false;
  }
};

constexpr int kGyroscopeCorrectionUnknowns =
    kGyroscopeCalibrationParameterCount + kGyroscopeEffectCoefficientCount;

// The index of the coefficient named `name` (GyroscopeEffectCoefficientName), -1 when none is.
inline int GyroscopeEffectCoefficientIndex(const std::string& name) {
  for (int c = 0; c < kGyroscopeEffectCoefficientCount; ++c)
    if (GyroscopeEffectCoefficientName(c) == name) return c;
  return -1;
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_CORRECTION_H_
