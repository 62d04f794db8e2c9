#ifndef ACCELCAL_MODELS_EFFECTS_NOISE_VARIANCE_H_
#define ACCELCAL_MODELS_EFFECTS_NOISE_VARIANCE_H_

// The ratio of each axis's true noise variance to the stated one (1 when the statement is
// right). No term in the prediction: the simulator scales its noise by it, discovery reads
// it from chi-square, and dead reckoning scales the run's noise by it.

#include "models/effect.h"

namespace accelcal {

struct NoiseVariance : EffectTerms {
  static constexpr EffectInfo kInfo = {
      "noise_variance",                                             // name
      "1",                                                          // unit
      "ratio of the true {axis} noise variance to the stated one",  // meaning
      Scope::kPerAxis,                                              // scope
      ActsIn::kBoth,                                                // acts_in
      Role::kNoiseRatio,                                            // role
      1.0,                                                          // neutral
      2.0,                                                          // example_size
      0,                                                            // force_degree
      1e4};                                                         // largest_deviation
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_NOISE_VARIANCE_H_
