// The gyroscope's registration of a build with one more effect
// (ACCELCAL_EXTRA_GYROSCOPE_EFFECTS_HEADER, included by models/gyroscope_effect_list.h after the
// built-in gyroscope effects are declared).

#include "rate_cubic.h"

namespace accelcal {
using GyroscopeEffects =
    AppendGyroscopeEffects<BuiltInGyroscopeEffects, GyroscopeRateCubicEffect>::Type;
}  // namespace accelcal
