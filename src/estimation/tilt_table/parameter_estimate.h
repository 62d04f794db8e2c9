#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_PARAMETER_ESTIMATE_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_PARAMETER_ESTIMATE_H_

// An estimate of the spec's model: a value for every parameter of the catalogue (the
// ones not estimated sit at their neutral value, or wherever the caller fixed them), the
// estimated ("free") parameters in the order of their covariance, and that covariance.
// The baseline's BaselineFit converts to one with free = (bias_x, scale_x, bias_y,
// scale_y), so code written for any estimate serves the baseline unchanged.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "estimation/tilt_table/baseline_parameters.h"
#include "models/effects.h"

namespace accelcal {

struct ParameterEstimate {
  ModelParameters<double> values;
  std::vector<Parameter> free;  // the covariance's order
  Eigen::MatrixXd covariance;   // free.size() x free.size(), in the spec's units
  // Each axis's noise correlation of consecutive samples (models/noise_model.h; 0: white),
  // which dead reckoning integrates with the variance noise_variance_k scales.
  std::array<double, 2> noise_correlation = {0.0, 0.0};

  // Index of `parameter` in `free`, or -1 when it was not estimated.
  int IndexOf(Parameter parameter) const;
  double Value(Parameter parameter) const { return values[parameter]; }
  // 0 for a parameter that was not estimated.
  double StandardDeviation(Parameter parameter) const;
};

ParameterEstimate FromBaselineFit(const BaselineFit& fit);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_PARAMETER_ESTIMATE_H_
