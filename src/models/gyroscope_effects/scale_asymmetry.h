#ifndef ACCELCAL_MODELS_GYROSCOPE_EFFECTS_SCALE_ASYMMETRY_H_
#define ACCELCAL_MODELS_GYROSCOPE_EFFECTS_SCALE_ASYMMETRY_H_

// gyroscope_scale_asymmetry_k [1]: axis k's gain differs between positive and negative rates,
// gain_k (1 + a_k) for positive ones and gain_k (1 - a_k) for negative ones:
//   v'_k += a_k |v_k|

#include <cmath>

#include "models/gyroscope_effect.h"

namespace accelcal {

struct GyroscopeScaleAsymmetryEffect {
  static constexpr GyroscopeEffectInfo kInfo = {
      "scale_asymmetry",
      "1",
      "an axis's gain differs between positive and negative rates",
      "turn the sensor both ways about every axis; the gains of a one-way session hide it",
      3,
      {"_x", "_y", "_z"},
      GyroscopeEffectStage::kAxis,
      false,
      true,
      {2e-3, -1e-3, 1.5e-3}};

  template <typename T>
  static void Apply(const T* a, const GyroscopeSampleContext<T>&, GyroscopeRateTerms<T>* terms) {
    using std::abs;
    for (int k = 0; k < 3; ++k) terms->per_axis[k] += a[k] * abs(terms->along[k]);
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_EFFECTS_SCALE_ASYMMETRY_H_
