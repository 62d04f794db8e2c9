#ifndef ACCELCAL_MODELS_EFFECTS_SCALE_NONLINEARITY_H_
#define ACCELCAL_MODELS_EFFECTS_SCALE_NONLINEARITY_H_

// k2_k [1/(m/s^2)]: each axis's second-order scale term, in the test and the run:
//   m_k += k2_k f_k^2

#include "models/effect.h"

namespace accelcal {

struct ScaleNonlinearity : EffectTerms {
  static constexpr EffectInfo kInfo = {"scale_nonlinearity",                          // name
                                       "1/(m/s^2)",                                   // unit
                                       "second-order scale term of the {axis} axis",  // meaning
                                       Scope::kPerAxis,                               // scope
                                       ActsIn::kBoth,                                 // acts_in
                                       Role::kEffect,                                 // role
                                       0.0,                                           // neutral
                                       0.001,  // example_size
                                       2,      // force_degree
                                       0.05};  // largest_deviation

  template <typename T>
  static void AddAxisTerms(const T& k2, double /*drift_coordinate*/, AxisPolynomial<T>* output) {
    output->c[2] += k2;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_SCALE_NONLINEARITY_H_
