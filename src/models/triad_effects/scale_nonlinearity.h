#ifndef ACCELCAL_MODELS_TRIAD_EFFECTS_SCALE_NONLINEARITY_H_
#define ACCELCAL_MODELS_TRIAD_EFFECTS_SCALE_NONLINEARITY_H_

// scale_nonlinearity_k [1/(m/s^2)]: each axis's second-order scale term, the tilt table's k2_k
// (models/effects/scale_nonlinearity.h) with the same name, unit and sign:
//   v_k = w_k + k2_k w_k^2
// (w_k the force along axis k, v_k its gain-corrected output, models/triad.h).

#include "models/triad_effect.h"

namespace accelcal {

struct TriadScaleNonlinearityEffect {
  static constexpr TriadEffectInfo kInfo = {"scale_nonlinearity",
                                            "1/(m/s^2)",
                                            "second-order scale term of the {axis} axis",
                                            3,
                                            {"_x", "_y", "_z"},
                                            "",
                                            2e-4};

  template <typename T>
  static void Apply(const T* k2, const TriadPoseContext& /*context*/, TriadPoseTerms<T>* terms) {
    for (int k = 0; k < 3; ++k) terms->quadratic[k] += k2[k];
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_EFFECTS_SCALE_NONLINEARITY_H_
