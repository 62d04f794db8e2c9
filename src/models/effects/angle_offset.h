#ifndef ACCELCAL_MODELS_EFFECTS_ANGLE_OFFSET_H_
#define ACCELCAL_MODELS_EFFECTS_ANGLE_OFFSET_H_

// delta [rad]: the tilt table's zero offset (tilt test only).
//   theta_true = theta_reported + delta

#include "models/effect.h"

namespace accelcal {

struct AngleOffset : EffectTerms {
  static constexpr EffectInfo kInfo = {
      "angle_offset",
      "rad",
      "table zero offset: theta_true = theta_reported + delta (calibration test only)",
      Scope::kShared,
      ActsIn::kCalibrationTest,
      Role::kEffect,
      /*neutral=*/0.0,
      /*example_size=*/0.004,
      /*force_degree=*/0};

  template <typename T>
  static void CorrectTableAngle(const T& angle_offset, T* theta_rad) {
    *theta_rad += angle_offset;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_ANGLE_OFFSET_H_
