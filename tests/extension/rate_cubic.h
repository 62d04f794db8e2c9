#ifndef ACCELCAL_TESTS_EXTENSION_RATE_CUBIC_H_
#define ACCELCAL_TESTS_EXTENSION_RATE_CUBIC_H_

// A research project's own gyroscope effect (docs/extending.md): a third-order scale term of each
// axis, odd in the rate as the gain is (a gain that grows with the rate's size both ways):
//   v'_k += rate_cubic_k v_k^3
// It is the whole of the effect: registered by one line (registered_gyroscope_effects.h), it
// reaches the ML fit and its residuals, the simulator, discovery's candidates, the calibration
// file and the studies with no other change.

#include "models/gyroscope_effect.h"

namespace accelcal {

struct GyroscopeRateCubicEffect {
  static constexpr GyroscopeEffectInfo kInfo = {
      "rate_cubic",
      "1/(rad/s)^2",
      "an axis's gain grows (or shrinks) with the square of the rate, both ways alike",
      "keep turns within the rate range the sensor will see in use, or calibrate the term",
      3,
      {"_x", "_y", "_z"},
      GyroscopeEffectStage::kAxis,
      false,
      true,
      {2e-3, -2e-3, 1.5e-3}};

  template <typename T>
  static void Apply(const T* c, const GyroscopeSampleContext<T>&, GyroscopeRateTerms<T>* terms) {
    for (int k = 0; k < 3; ++k) {
      const T v = terms->along[k];
      terms->per_axis[k] += c[k] * v * v * v;
    }
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_TESTS_EXTENSION_RATE_CUBIC_H_
