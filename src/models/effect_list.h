#ifndef ACCELCAL_MODELS_EFFECT_LIST_H_
#define ACCELCAL_MODELS_EFFECT_LIST_H_

// The registration: every effect of the catalogue, one line each. The order is the
// catalogue's (the spec's), except that the baseline's parameters come first, axis by axis
// (bias_x, scale_x, bias_y, scale_y) as in the reference report; every other effect's
// parameters follow in this order, x before y.
//
// A build may register more effects without editing this file: configure with
// -DACCELCAL_EXTRA_EFFECTS_HEADER=path/to/header.h, a header that defines
// `using RegisteredEffects = AppendEffects<BuiltInEffects, MyEffect>::Type;`
// (docs/extending.md; tests/extension/ builds the library that way).

#ifdef ACCELCAL_REGISTRY_INDEPENDENT
#error \
    "a source of accelcal_core includes the effects registry: move it to accelcal_add_library's sources (src/CMakeLists.txt)"
#endif

#include "models/effect.h"
#include "models/effects/angle_offset.h"
#include "models/effects/bias.h"
#include "models/effects/bias_drift.h"
#include "models/effects/noise_variance.h"
#include "models/effects/nonorthogonality.h"
#include "models/effects/run_bias_shift.h"
#include "models/effects/scale.h"
#include "models/effects/scale_nonlinearity.h"

namespace accelcal {

using BuiltInEffects = EffectList<Bias,               //
                                  Scale,              //
                                  AngleOffset,        //
                                  Nonorthogonality,   //
                                  BiasDrift,          //
                                  ScaleNonlinearity,  //
                                  RunBiasShift,       //
                                  NoiseVariance>;

}  // namespace accelcal

#ifdef ACCELCAL_EXTRA_EFFECTS_HEADER
#include ACCELCAL_EXTRA_EFFECTS_HEADER
#else
namespace accelcal {
using RegisteredEffects = BuiltInEffects;
}  // namespace accelcal
#endif

#endif  // ACCELCAL_MODELS_EFFECT_LIST_H_
