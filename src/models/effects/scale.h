#ifndef ACCELCAL_MODELS_EFFECTS_SCALE_H_
#define ACCELCAL_MODELS_EFFECTS_SCALE_H_

// s_k [1]: the scale-factor error of each axis, in the test and the run (baseline).
//   m_k += s_k f_k

#include "models/effect.h"

namespace accelcal {

struct Scale : EffectTerms {
  static constexpr EffectInfo kInfo = {"scale",
                                       "1",
                                       "scale-factor error of the {axis} axis",
                                       Scope::kPerAxis,
                                       ActsIn::kBoth,
                                       Role::kBaseline,
                                       /*neutral=*/0.0,
                                       /*example_size=*/0.0,
                                       /*force_degree=*/1};

  template <typename T>
  static void AddAxisTerms(const T& scale, double /*drift_coordinate*/, AxisPolynomial<T>* output) {
    output->c[1] += scale;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_SCALE_H_
