#ifndef ACCELCAL_MODELS_EFFECTS_SCALE_H_
#define ACCELCAL_MODELS_EFFECTS_SCALE_H_

// s_k [1]: the scale-factor error of each axis, in the test and the run (baseline).
//   m_k += s_k f_k

#include "models/effect.h"

namespace accelcal {

struct Scale : EffectTerms {
  static constexpr EffectInfo kInfo = {"scale",                                  // name
                                       "1",                                      // unit
                                       "scale-factor error of the {axis} axis",  // meaning
                                       Scope::kPerAxis,                          // scope
                                       ActsIn::kBoth,                            // acts_in
                                       Role::kBaseline,                          // role
                                       0.0,                                      // neutral
                                       0.0,                                      // example_size
                                       1,                                        // force_degree
                                       0.5};  // largest_deviation

  template <typename T>
  static void AddAxisTerms(const T& scale, double /*drift_coordinate*/, AxisPolynomial<T>* output) {
    output->c[1] += scale;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_SCALE_H_
