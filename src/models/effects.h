#ifndef ACCELCAL_MODELS_EFFECTS_H_
#define ACCELCAL_MODELS_EFFECTS_H_

// The parameter catalogue of ../shared/spec/error-model.md: the baseline (bias and scale
// per axis) and every effect beyond it, with the names outputs use, their units and
// meaning. ModelParameters holds a value for each; ParameterValue is the one place
// that maps a name to its field, so the simulator's --set, the scenario files, the
// estimators' outputs and the discovery candidates all agree on what a name means.

#include <array>
#include <string>

#include "models/sensor_model.h"

namespace accelcal {

enum class Parameter {
  kBiasX,
  kScaleX,
  kBiasY,
  kScaleY,
  kAngleOffset,
  kNonorthogonality,
  kBiasDriftX,
  kBiasDriftY,
  kScaleNonlinearityX,
  kScaleNonlinearityY,
  kRunBiasShiftX,
  kRunBiasShiftY,
  kNoiseVarianceX,
  kNoiseVarianceY,
};
constexpr int kParameterCount = 14;

struct ParameterInfo {
  Parameter parameter;
  const char* name;  // as in the spec's outputs
  const char* unit;
  const char* meaning;
  bool baseline;   // part of the reference report's model
  double neutral;  // the value at which the effect is absent
  // A size at which the effect is plainly visible on the course-sized experiment (the
  // simulator's demonstration knob, used by the coverage study's effect table).
  double example_size;
};

// Every parameter, baseline first, in the spec's order.
const std::array<ParameterInfo, kParameterCount>& ParameterCatalogue();

// The entry named `name`, or nullptr.
const ParameterInfo* FindParameter(const std::string& name);
const ParameterInfo& Info(Parameter parameter);

// All parameters of the spec's model. noise_variance_k is an effect like the others: the
// ratio of the true noise variance to the stated one (1 when the statement is right).
template <typename T>
struct ModelParameters {
  SensorErrors<T> sensor;
  T angle_offset = T(0.0);  // delta, rad (calibration test only)
  T noise_variance_ratio_x = T(1.0);
  T noise_variance_ratio_y = T(1.0);
};

template <typename T>
T& ParameterValue(ModelParameters<T>* parameters, Parameter parameter) {
  switch (parameter) {
    case Parameter::kBiasX:
      return parameters->sensor.x.bias;
    case Parameter::kScaleX:
      return parameters->sensor.x.scale;
    case Parameter::kBiasY:
      return parameters->sensor.y.bias;
    case Parameter::kScaleY:
      return parameters->sensor.y.scale;
    case Parameter::kAngleOffset:
      return parameters->angle_offset;
    case Parameter::kNonorthogonality:
      return parameters->sensor.nonorthogonality;
    case Parameter::kBiasDriftX:
      return parameters->sensor.x.bias_drift;
    case Parameter::kBiasDriftY:
      return parameters->sensor.y.bias_drift;
    case Parameter::kScaleNonlinearityX:
      return parameters->sensor.x.scale_nonlinearity;
    case Parameter::kScaleNonlinearityY:
      return parameters->sensor.y.scale_nonlinearity;
    case Parameter::kRunBiasShiftX:
      return parameters->sensor.x.run_bias_shift;
    case Parameter::kRunBiasShiftY:
      return parameters->sensor.y.run_bias_shift;
    case Parameter::kNoiseVarianceX:
      return parameters->noise_variance_ratio_x;
    case Parameter::kNoiseVarianceY:
      return parameters->noise_variance_ratio_y;
  }
  return parameters->angle_offset;  // unreachable: every enumerator is handled above
}

template <typename T>
T ParameterValue(const ModelParameters<T>& parameters, Parameter parameter) {
  ModelParameters<T> copy = parameters;
  return ParameterValue(&copy, parameter);
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_H_
