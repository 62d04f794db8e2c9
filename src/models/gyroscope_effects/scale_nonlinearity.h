#ifndef ACCELCAL_MODELS_GYROSCOPE_EFFECTS_SCALE_NONLINEARITY_H_
#define ACCELCAL_MODELS_GYROSCOPE_EFFECTS_SCALE_NONLINEARITY_H_

// gyroscope_scale_nonlinearity_k [1/(rad/s)]: axis k's gain changes with the rate, a
// second-order scale term:
//   v'_k += n_k v_k^2

#include "models/gyroscope_effect.h"

namespace accelcal {

struct GyroscopeScaleNonlinearityEffect {
  static constexpr GyroscopeEffectInfo kInfo = {
      "scale_nonlinearity",
      "1/(rad/s)",
      "an axis's gain changes with the rate (a second-order scale term)",
      "keep turns within the rate range the sensor will see in use, or calibrate the term",
      3,
      {"_x", "_y", "_z"},
      GyroscopeEffectStage::kAxis,
      false,
      true,
      {1e-3, -2e-3, 1.5e-3}};

  template <typename T>
  static void Apply(const T* n, const GyroscopeSampleContext<T>&, GyroscopeRateTerms<T>* terms) {
    for (int k = 0; k < 3; ++k) terms->per_axis[k] += n[k] * terms->along[k] * terms->along[k];
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_EFFECTS_SCALE_NONLINEARITY_H_
