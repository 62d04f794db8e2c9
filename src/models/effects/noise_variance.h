#ifndef ACCELCAL_MODELS_EFFECTS_NOISE_VARIANCE_H_
#define ACCELCAL_MODELS_EFFECTS_NOISE_VARIANCE_H_

// The ratio of each axis's true noise variance to the stated one (1 when the statement is
// right). No term in the prediction: the simulator scales its noise by it, discovery reads
// it from chi-square, and dead reckoning scales the run's noise by it.

#include "models/effect.h"

namespace accelcal {

struct NoiseVariance : EffectTerms {
  static constexpr EffectInfo kInfo = {"noise_variance",
                                       "1",
                                       "ratio of the true {axis} noise variance to the stated one",
                                       Scope::kPerAxis,
                                       ActsIn::kBoth,
                                       Role::kNoiseRatio,
                                       /*neutral=*/1.0,
                                       /*example_size=*/2.0,
                                       /*force_degree=*/0};
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_NOISE_VARIANCE_H_
