#ifndef ACCELCAL_MODELS_TRIAD_EFFECTS_GRAVITY_ERROR_H_
#define ACCELCAL_MODELS_TRIAD_EFFECTS_GRAVITY_ERROR_H_

// gravity_error [m/s^2]: the local gravity minus the stated --g. Static poses cannot see it:
// every pose's force is scaled by (g + e)/g, which the three gains absorb exactly (each gain
// times g/(g + e)), so the fit is unchanged and the gains carry the error. Registered so that
// discovery says so instead of leaving the question open.

#include "models/triad_effect.h"

namespace accelcal {

struct TriadGravityErrorEffect {
  static constexpr TriadEffectInfo kInfo = {
      "gravity_error",
      "m/s^2",
      "local gravity minus the stated g",
      1,
      {"", "", ""},
      "the common scale of gain_x, gain_y, gain_z (a gravity error e scales every gain by "
      "g/(g + e))",
      0.01,
      "the session's local gravity, not a property of the sensor"};

  template <typename T>
  static void Apply(const T* error, const TriadPoseContext& /*context*/, TriadPoseTerms<T>* terms) {
    terms->gravity += error[0];
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_EFFECTS_GRAVITY_ERROR_H_
