#ifndef ACCELCAL_MODELS_GYROSCOPE_CORRECTION_H_
#define ACCELCAL_MODELS_GYROSCOPE_CORRECTION_H_

// A gyroscope's calibration as a correction applies it: the 9 parameters and the offset
// (models/gyroscope.h) and the effect coefficients (models/gyroscope_effect_list.h) of the model
// discovery settled on. The rate is GyroscopeCorrectedRate's, in the correction's direction
// already; f is the specific force the calibrated accelerometer measures at the same sample (the
// g-sensitivity's term). The coefficients of an effect that belongs to its session
// (GyroscopeEffectInfo::session_only) are carried, not applied.

#include <Eigen/Core>
#include <vector>

#include "models/gyroscope.h"
#include "models/gyroscope_effect_list.h"
#include "models/gyroscope_units.h"

namespace accelcal {

struct GyroscopeCalibrationModel {
  GyroscopeParameters parameters{};
  GyroscopeOffset offset{};
  GyroscopeEffectCoefficients effects{};  // 0 for those the correction does not apply
  std::vector<int> effects_in_file;       // applied: indices into the block, in the file's order
  // Carried by the file but not applied: its effect belongs to the session calibrated
  // (GyroscopeEffectInfo::session_only).
  std::vector<int> effects_not_applied;
  // (kGyroscopeCalibrationParameterCount + kGyroscopeEffectCoefficientCount) square: the 9, the
  // offset, then the block; rows and columns of coefficients not applied are 0.
  Eigen::MatrixXd covariance;
  GyroscopeOutputUnit unit = GyroscopeOutputUnit::kCount;

  bool has_effects() const { return !effects_in_file.empty(); }
  // Whether the correction needs the specific force (a term of the rate stage is carried).
  bool needs_specific_force() const {
    for (const int c : effects_in_file)
      if (GyroscopeEffectInfos()[GyroscopeEffectOf(c)].stage == GyroscopeEffectStage::kRate)
        return true;
    return false;
  }
};

// Whether coefficient c of the block is applied by a correction (its effect is a property of the
// sensor).
inline bool GyroscopeEffectAppliedInUse(int c) {
  return GyroscopeEffectInfos()[GyroscopeEffectOf(c)].session_only == nullptr;
}

constexpr int kGyroscopeCorrectionUnknowns =
    kGyroscopeCalibrationParameterCount + kGyroscopeEffectCoefficientCount;

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_CORRECTION_H_
