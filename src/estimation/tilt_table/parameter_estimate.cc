#include "estimation/tilt_table/parameter_estimate.h"

#include <cmath>

namespace accelcal {

int ParameterEstimate::IndexOf(Parameter parameter) const {
  for (size_t i = 0; i < free.size(); ++i) {
    if (free[i] == parameter) return static_cast<int>(i);
  }
  return -1;
}

double ParameterEstimate::StandardDeviation(Parameter parameter) const {
  const int index = IndexOf(parameter);
  return index < 0 ? 0.0 : std::sqrt(covariance(index, index));
}

ParameterEstimate FromBaselineFit(const BaselineFit& fit) {
  ParameterEstimate estimate;
  estimate.free.assign(kBaselineParameters.begin(), kBaselineParameters.end());
  for (const Parameter parameter : kBaselineParameters) {
    estimate.values[parameter] = fit.Value(parameter);
  }
  estimate.covariance = fit.covariance;
  return estimate;
}

}  // namespace accelcal
