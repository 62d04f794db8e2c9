// The triad's registration of a build with one more effect (ACCELCAL_EXTRA_TRIAD_EFFECTS_HEADER,
// included by models/triad_effect_list.h after the built-in triad effects are declared).

#include "offset_warmup.h"

namespace accelcal {
using TriadEffects = AppendTriadEffects<BuiltInTriadEffects, TriadOffsetWarmupEffect>::Type;
}  // namespace accelcal
