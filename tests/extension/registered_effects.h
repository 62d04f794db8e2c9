// The registration of a build with one more effect (ACCELCAL_EXTRA_EFFECTS_HEADER, included
// by models/effect_list.h after the built-in effects are declared).

#include "scale_cubic.h"

namespace accelcal {
using RegisteredEffects = AppendEffects<BuiltInEffects, ScaleCubic>::Type;
}  // namespace accelcal
