#ifndef ACCELCAL_MODELS_EFFECTS_ANGLE_OFFSET_H_
#define ACCELCAL_MODELS_EFFECTS_ANGLE_OFFSET_H_

// delta [rad]: the tilt table's zero offset (tilt test only).
//   theta_true = theta_reported + delta

#include "models/effect.h"

namespace accelcal {

struct AngleOffset : EffectTerms {
  static constexpr EffectInfo kInfo = {
      "angle_offset",                                                                    // name
      "rad",                                                                             // unit
      "table zero offset: theta_true = theta_reported + delta (calibration test only)",  // meaning
      Scope::kShared,                                                                    // scope
      ActsIn::kCalibrationTest,                                                          // acts_in
      Role::kEffect,                                                                     // role
      0.0,                                                                               // neutral
      0.004,     // example_size
      0,         // force_degree
      3.14159};  // largest_deviation

  template <typename T>
  static void CorrectTableAngle(const T& angle_offset, T* theta_rad) {
    *theta_rad += angle_offset;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_ANGLE_OFFSET_H_
