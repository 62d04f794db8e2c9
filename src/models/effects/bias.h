#ifndef ACCELCAL_MODELS_EFFECTS_BIAS_H_
#define ACCELCAL_MODELS_EFFECTS_BIAS_H_

// b_k [m/s^2]: the constant bias of each axis, in the test and the run (baseline).
//   m_k += b_k

#include "models/effect.h"

namespace accelcal {

struct Bias : EffectTerms {
  static constexpr EffectInfo kInfo = {"bias",                              // name
                                       "m/s^2",                             // unit
                                       "constant bias of the {axis} axis",  // meaning
                                       Scope::kPerAxis,                     // scope
                                       ActsIn::kBoth,                       // acts_in
                                       Role::kBaseline,                     // role
                                       0.0,                                 // neutral
                                       0.0,                                 // example_size
                                       0,                                   // force_degree
                                       100.0};                              // largest_deviation

  template <typename T>
  static void AddAxisTerms(const T& bias, double /*drift_coordinate*/, AxisPolynomial<T>* output) {
    output->c[0] += bias;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_BIAS_H_
