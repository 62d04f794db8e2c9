#ifndef ACCELCAL_MODELS_GYROSCOPE_EFFECTS_G_SENSITIVITY_H_
#define ACCELCAL_MODELS_GYROSCOPE_EFFECTS_G_SENSITIVITY_H_

// gyroscope_g_sensitivity_qk [(rad/s)/(m/s^2)]: the gyroscope reads a rate proportional to the
// specific force (imucal's K_ga), G row-major (row q: the rate's axis, column k: the force's):
//   w -= G f
// f: the specific force the calibrated accelerometer measures at the same sample (m/s^2).

#include "models/gyroscope_effect.h"

namespace accelcal {

struct GyroscopeGSensitivityEffect {
  static constexpr GyroscopeEffectInfo kInfo = {
      "g_sensitivity",
      "(rad/s)/(m/s^2)",
      "the gyroscope reads a rate proportional to the specific force (imucal's K_ga)",
      "calibrate it with the rest (its 9 terms are in the calibration) or mount the sensor so "
      "that vibration and tilt do not reach it",
      9,
      {"_xx", "_xy", "_xz", "_yx", "_yy", "_yz", "_zx", "_zy", "_zz"},
      GyroscopeEffectStage::kRate,
      true,
      false,
      {2e-4, 1e-4, 1e-4, 1e-4, 2e-4, 1e-4, 1e-4, 1e-4, 2e-4}};

  template <typename T>
  static void Apply(const T* g, const GyroscopeSampleContext<T>& context,
                    GyroscopeRateTerms<T>* terms) {
    const T* f = context.specific_force;
    for (int q = 0; q < 3; ++q) {
      terms->rate_shift[q] -= g[3 * q] * f[0] + g[3 * q + 1] * f[1] + g[3 * q + 2] * f[2];
    }
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_EFFECTS_G_SENSITIVITY_H_
