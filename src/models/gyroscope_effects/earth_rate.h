#ifndef ACCELCAL_MODELS_GYROSCOPE_EFFECTS_EARTH_RATE_H_
#define ACCELCAL_MODELS_GYROSCOPE_EFFECTS_EARTH_RATE_H_

// gyroscope_earth_rate [rad/s]: the vertical part of the Earth's rotation, Omega sin(latitude)
// (7.29e-5 rad/s at a pole, 0 on the equator), about the up direction, which the specific force
// points along wherever the sensor is not accelerating: a gyroscope at rest reads it, and a turn
// integrates it. The calibrated rate is the body's rate against the ground:
//   w -= e f / |f|
// f: the specific force the calibrated accelerometer measures at the same sample (m/s^2).
//
// Not the sensor's: every session on Earth sees it. The ML fit (estimation/gyroscope/
// gyroscope_ml_calibration.h) holds it in every model where the Earth's rate is counted: given
// exactly by the latitude, or estimated with the prior N(0, Omega^2) where it is not, so that a
// quiet gyroscope's poses determine it and a noisy one's bound it; it is never one of
// discovery's candidates (a g-sensitivity G = e/g I has the same pattern at rest), and a
// calibration file never carries it. The horizontal part, whose direction in the body is not
// known, is the fit's noise.

#include <cmath>

#include "models/gyroscope_effect.h"

namespace accelcal {

struct GyroscopeEarthRateEffect {
  static constexpr GyroscopeEffectInfo kInfo = {
      "earth_rate",
      "rad/s",
      "the Earth's rotation about the up direction, Omega sin(latitude), which the gyroscope reads "
      "at rest",
      "give the latitude (--latitude_deg) so that it is known rather than estimated",
      1,
      {""},
      GyroscopeEffectStage::kRate,
      true,
      false,
      {5.156e-5},  // Omega sin(45 deg)
      "the Earth's rotation is a rate the body turns at, which `apply` leaves in the rates",
      "the Earth's rate: every session sees it, so the fit holds it in every model (known from "
      "--latitude_deg, else estimated with its prior) and discovery never names it"};

  template <typename T>
  static void Apply(const T* e, const GyroscopeSampleContext<T>& context,
                    GyroscopeRateTerms<T>* terms) {
    using std::sqrt;
    const T* f = context.specific_force;
    if (f == nullptr) return;
    const T norm2 = f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
    if (!(norm2 > T(0.0))) return;
    const T scale = e[0] / sqrt(norm2);
    for (int q = 0; q < 3; ++q) terms->rate_shift[q] -= scale * f[q];
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_EFFECTS_EARTH_RATE_H_
