#include "models/effects.h"

#include <vector>

namespace accelcal {
namespace {

// "{axis}" in a per-axis effect's meaning, replaced by the axis' letter.
std::string ForAxis(std::string text, char axis) {
  const std::string placeholder = "{axis}";
  for (size_t at = text.find(placeholder); at != std::string::npos;
       at = text.find(placeholder, at + 1)) {
    text.replace(at, placeholder.size(), 1, axis);
  }
  return text;
}

}  // namespace

const std::array<ParameterInfo, kParameterCount>& ParameterCatalogue() {
  // The names and meanings live as long as the program; the entries point into them.
  static const std::vector<std::string>* const texts = [] {
    auto* strings = new std::vector<std::string>;
    for (int i = 0; i < kParameterCount; ++i) {
      const EffectInfo& effect = EffectOf(Parameter(i));
      const char axis = kParameterSlots[i].axis == SensingAxis::kX ? 'x' : 'y';
      const bool per_axis = effect.scope == Scope::kPerAxis;
      strings->push_back(per_axis ? std::string(effect.name) + '_' + axis : effect.name);
      strings->push_back(per_axis ? ForAxis(effect.meaning, axis) : effect.meaning);
    }
    return strings;
  }();
  static const std::array<ParameterInfo, kParameterCount> catalogue = [] {
    std::array<ParameterInfo, kParameterCount> entries;
    for (int i = 0; i < kParameterCount; ++i) {
      const EffectInfo& effect = EffectOf(Parameter(i));
      entries[i] = {Parameter(i),
                    (*texts)[2 * i].c_str(),
                    effect.unit,
                    (*texts)[2 * i + 1].c_str(),
                    effect.role == Role::kBaseline,
                    effect.neutral,
                    effect.example_size,
                    &effect,
                    kParameterSlots[i].axis};
    }
    return entries;
  }();
  return catalogue;
}

const ParameterInfo* FindParameter(const std::string& name) {
  for (const ParameterInfo& info : ParameterCatalogue()) {
    if (name == info.name) return &info;
  }
  return nullptr;
}

const ParameterInfo& Info(Parameter parameter) { return ParameterCatalogue()[parameter.index()]; }

}  // namespace accelcal
