#ifndef ACCELCAL_MODELS_EFFECT_NAMES_H_
#define ACCELCAL_MODELS_EFFECT_NAMES_H_

// The effects of the catalogue by name, as users write them (--effects, help texts).

#include <string>
#include <vector>

#include "common/status.h"
#include "models/effects.h"

namespace accelcal {

// The effects the joint model may estimate beyond bias and scale, in catalogue order (every
// parameter that is neither baseline nor a noise ratio).
std::vector<Parameter> EstimableEffects();

// Their names joined by `separator`, e.g. for a help text.
std::string EstimableEffectNames(const std::string& separator = ", ");

// Parses "angle_offset,nonorthogonality,..." (or "none", or "all") into effects, each once,
// in the order given.
Status ParseEffects(const std::string& list, std::vector<Parameter>* effects);

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECT_NAMES_H_
