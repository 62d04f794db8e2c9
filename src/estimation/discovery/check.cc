#include "estimation/discovery/check.h"

#include "estimation/statistics/diagnostics.h"

namespace accelcal {

const char* ShapeClassName(ShapeClass shape_class) {
  switch (shape_class) {
    case ShapeClass::kNoise:
      return "noise";
    case ShapeClass::kOrientation:
      return "orientation";
    case ShapeClass::kTime:
      return "time";
    case ShapeClass::kTurnDirection:
      return "turn_direction";
    case ShapeClass::kPoseOrder:
      return "pose_order";
    case ShapeClass::kFullScale:
      return "full_scale";
    case ShapeClass::kTurnMotion:
      return "turn_motion";
  }
  return "noise";
}

std::string WhatRemains(const ResidualCheck& check) {
  return check.advice.empty() ? check.description : check.description + ": " + check.advice;
}

int FlagByHolm(double alpha, std::vector<ResidualCheck>* checks) {
  std::vector<double> p_values;
  for (const ResidualCheck& check : *checks) p_values.push_back(check.p_value);
  const std::vector<bool> rejected = HolmRejections(p_values, alpha);
  int flagged = 0;
  for (size_t i = 0; i < checks->size(); ++i) {
    (*checks)[i].flagged = rejected[i];
    flagged += rejected[i];
  }
  return flagged;
}

}  // namespace accelcal
