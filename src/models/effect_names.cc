#include "models/effect_names.h"

#include <algorithm>
#include <sstream>

namespace accelcal {

std::vector<Parameter> EstimableEffects() {
  std::vector<Parameter> effects;
  for (const ParameterInfo& info : ParameterCatalogue()) {
    if (!info.baseline && !IsNoiseRatio(info.parameter)) effects.push_back(info.parameter);
  }
  return effects;
}

std::string EstimableEffectNames(const std::string& separator) {
  std::string names;
  for (const Parameter effect : EstimableEffects()) {
    names += (names.empty() ? "" : separator) + Info(effect).name;
  }
  return names;
}

Status ParseEffects(const std::string& list, std::vector<Parameter>* effects) {
  effects->clear();
  if (list.empty() || list == "none") return Status::Ok();
  std::istringstream stream(list);
  std::string name;
  while (std::getline(stream, name, ',')) {
    if (name.empty()) continue;
    if (name == "all") {
      for (const Parameter effect : EstimableEffects()) {
        if (std::find(effects->begin(), effects->end(), effect) == effects->end())
          effects->push_back(effect);
      }
      continue;
    }
    const ParameterInfo* info = FindParameter(name);
    if (info == nullptr || info->baseline) {
      return Status::Error("'" + name +
                           "' is not an effect the joint model estimates; choose from " +
                           EstimableEffectNames() + " (bias and scale are always estimated)");
    }
    if (IsNoiseRatio(info->parameter)) {
      return Status::Error(std::string(info->name) +
                           " is not a model parameter: it is read from chi-square (see discover)");
    }
    if (std::find(effects->begin(), effects->end(), info->parameter) == effects->end()) {
      effects->push_back(info->parameter);
    }
  }
  return Status::Ok();
}

}  // namespace accelcal
