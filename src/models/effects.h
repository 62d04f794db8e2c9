#ifndef ACCELCAL_MODELS_EFFECTS_H_
#define ACCELCAL_MODELS_EFFECTS_H_

// The parameter catalogue of ../shared/spec/error-model.md, derived from the registered
// effects (models/effect_list.h): the baseline (bias and scale per axis) and every effect
// beyond it, with the names outputs use, their units and meaning. A Parameter is a place in
// the catalogue; ModelParameters holds a value for each. So the simulator's --set, the
// scenario files, the estimators' outputs and the discovery candidates all agree on what a
// name means, and an effect registered later has all of them without further code.

#include <array>
#include <string>
#include <type_traits>

#include "models/effect_list.h"

namespace accelcal {

constexpr int kEffectCount = RegisteredEffects::kSize;

namespace internal {

template <typename List>
struct EffectInfos;
template <typename... Effects>
struct EffectInfos<EffectList<Effects...>> {
  static constexpr std::array<EffectInfo, sizeof...(Effects)> kValue = {{Effects::kInfo...}};
};

template <typename Effect, typename List>
struct EffectIndex;
template <typename Effect, typename... Effects>
struct EffectIndex<Effect, EffectList<Effects...>> {
  static constexpr int Find() {
    constexpr bool same[] = {std::is_same_v<Effect, Effects>...};
    for (int i = 0; i < static_cast<int>(sizeof...(Effects)); ++i) {
      if (same[i]) return i;
    }
    return -1;
  }
  static constexpr int kValue = Find();
};

}  // namespace internal

// The registered effects' declarations, in registration order.
inline constexpr std::array<EffectInfo, kEffectCount> kEffectInfos =
    internal::EffectInfos<RegisteredEffects>::kValue;

// Where `Effect` is in the registration.
template <typename Effect>
constexpr int EffectIndexOf() {
  constexpr int index = internal::EffectIndex<Effect, RegisteredEffects>::kValue;
  static_assert(index >= 0, "the effect is not registered in models/effect_list.h");
  return index;
}

// One parameter: an effect and, for a per-axis effect, the axis (kX for a shared one).
struct ParameterSlot {
  int effect = 0;
  SensingAxis axis = SensingAxis::kX;
};

constexpr int CountParameters() {
  int count = 0;
  for (const EffectInfo& info : kEffectInfos) count += info.scope == Scope::kPerAxis ? 2 : 1;
  return count;
}
constexpr int kParameterCount = CountParameters();

// The catalogue's order: the baseline axis by axis, then each effect (x before y).
constexpr std::array<ParameterSlot, kParameterCount> MakeParameterSlots() {
  std::array<ParameterSlot, kParameterCount> slots = {};
  int next = 0;
  for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
    for (int e = 0; e < kEffectCount; ++e) {
      const EffectInfo& info = kEffectInfos[e];
      if (info.role != Role::kBaseline) continue;
      if (info.scope == Scope::kPerAxis || axis == SensingAxis::kX) slots[next++] = {e, axis};
    }
  }
  for (int e = 0; e < kEffectCount; ++e) {
    const EffectInfo& info = kEffectInfos[e];
    if (info.role == Role::kBaseline) continue;
    slots[next++] = {e, SensingAxis::kX};
    if (info.scope == Scope::kPerAxis) slots[next++] = {e, SensingAxis::kY};
  }
  return slots;
}
inline constexpr std::array<ParameterSlot, kParameterCount> kParameterSlots = MakeParameterSlots();

// A parameter of the catalogue (an index into it). The built-in ones have names here for
// the code that needs a particular one; any parameter, registered later or not, is found
// by name with FindParameter or by effect with ParameterOf.
class Parameter {
 public:
  constexpr Parameter() = default;
  constexpr explicit Parameter(int index) : index_(index) {}
  constexpr int index() const { return index_; }
  friend constexpr bool operator==(Parameter a, Parameter b) { return a.index_ == b.index_; }
  friend constexpr bool operator!=(Parameter a, Parameter b) { return a.index_ != b.index_; }
  friend constexpr bool operator<(Parameter a, Parameter b) { return a.index_ < b.index_; }

  static const Parameter kBiasX;
  static const Parameter kScaleX;
  static const Parameter kBiasY;
  static const Parameter kScaleY;
  static const Parameter kAngleOffset;
  static const Parameter kNonorthogonality;
  static const Parameter kBiasDriftX;
  static const Parameter kBiasDriftY;
  static const Parameter kScaleNonlinearityX;
  static const Parameter kScaleNonlinearityY;
  static const Parameter kRunBiasShiftX;
  static const Parameter kRunBiasShiftY;
  static const Parameter kNoiseVarianceX;
  static const Parameter kNoiseVarianceY;

 private:
  int index_ = 0;
};

// The parameter of `Effect` (of its `axis` when it is per-axis).
template <typename Effect>
constexpr Parameter ParameterOf(SensingAxis axis = SensingAxis::kX) {
  constexpr int effect = EffectIndexOf<Effect>();
  if (kEffectInfos[effect].scope == Scope::kShared) axis = SensingAxis::kX;
  for (int i = 0; i < kParameterCount; ++i) {
    if (kParameterSlots[i].effect == effect && kParameterSlots[i].axis == axis) return Parameter(i);
  }
  return Parameter(-1);  // unreachable for a registered effect
}

inline constexpr Parameter Parameter::kBiasX = ParameterOf<Bias>(SensingAxis::kX);
inline constexpr Parameter Parameter::kScaleX = ParameterOf<Scale>(SensingAxis::kX);
inline constexpr Parameter Parameter::kBiasY = ParameterOf<Bias>(SensingAxis::kY);
inline constexpr Parameter Parameter::kScaleY = ParameterOf<Scale>(SensingAxis::kY);
inline constexpr Parameter Parameter::kAngleOffset = ParameterOf<AngleOffset>();
inline constexpr Parameter Parameter::kNonorthogonality = ParameterOf<Nonorthogonality>();
inline constexpr Parameter Parameter::kBiasDriftX = ParameterOf<BiasDrift>(SensingAxis::kX);
inline constexpr Parameter Parameter::kBiasDriftY = ParameterOf<BiasDrift>(SensingAxis::kY);
inline constexpr Parameter Parameter::kScaleNonlinearityX =
    ParameterOf<ScaleNonlinearity>(SensingAxis::kX);
inline constexpr Parameter Parameter::kScaleNonlinearityY =
    ParameterOf<ScaleNonlinearity>(SensingAxis::kY);
inline constexpr Parameter Parameter::kRunBiasShiftX = ParameterOf<RunBiasShift>(SensingAxis::kX);
inline constexpr Parameter Parameter::kRunBiasShiftY = ParameterOf<RunBiasShift>(SensingAxis::kY);
inline constexpr Parameter Parameter::kNoiseVarianceX = ParameterOf<NoiseVariance>(SensingAxis::kX);
inline constexpr Parameter Parameter::kNoiseVarianceY = ParameterOf<NoiseVariance>(SensingAxis::kY);

constexpr const EffectInfo& EffectOf(Parameter parameter) {
  return kEffectInfos[kParameterSlots[parameter.index()].effect];
}

struct ParameterInfo {
  Parameter parameter;
  const char* name;  // as in the spec's outputs
  const char* unit;
  const char* meaning;
  bool baseline;   // part of the reference report's model
  double neutral;  // the value at which the effect is absent
  double example_size;
  const EffectInfo* effect;  // the registered effect it belongs to
  SensingAxis axis;          // its axis (kX for a shared effect)
};

// Every parameter, in the catalogue's order (see MakeParameterSlots).
const std::array<ParameterInfo, kParameterCount>& ParameterCatalogue();

// The entry named `name`, or nullptr.
const ParameterInfo* FindParameter(const std::string& name);
const ParameterInfo& Info(Parameter parameter);

// Not a model parameter: a noise variance ratio (read from chi-square, not estimated).
constexpr bool IsNoiseRatio(Parameter parameter) {
  return EffectOf(parameter).role == Role::kNoiseRatio;
}
// Acts only in the vehicle run, so only a landmark can reveal it.
constexpr bool ActsOnlyInRun(Parameter parameter) {
  return EffectOf(parameter).acts_in == ActsIn::kVehicleRun;
}

// The model parameters (noise ratios excluded) acting in `phase`, in catalogue order; with
// `axis`, only the shared ones and those of that axis. These are the parameter blocks of
// the residuals: one axis's tilt-test residual depends on CalibrationParameters(axis), the
// run's endpoint on RunParameters().
constexpr bool ActsOn(Parameter parameter, Phase phase, bool any_axis, SensingAxis axis) {
  const EffectInfo& effect = EffectOf(parameter);
  return effect.role != Role::kNoiseRatio && ActsInPhase(effect, phase) &&
         (any_axis || effect.scope == Scope::kShared ||
          kParameterSlots[parameter.index()].axis == axis);
}

constexpr int CountActing(Phase phase, bool any_axis) {
  int count = 0;
  for (int i = 0; i < kParameterCount; ++i)
    count += ActsOn(Parameter(i), phase, any_axis, SensingAxis::kX) ? 1 : 0;
  return count;
}

template <int kCount>
constexpr std::array<Parameter, kCount> Acting(Phase phase, bool any_axis, SensingAxis axis) {
  std::array<Parameter, kCount> parameters = {};
  int next = 0;
  for (int i = 0; i < kParameterCount; ++i) {
    if (ActsOn(Parameter(i), phase, any_axis, axis)) parameters[next++] = Parameter(i);
  }
  return parameters;
}

constexpr int kCalibrationParameterCount = CountActing(Phase::kCalibrationTest, false);
constexpr int kRunParameterCount = CountActing(Phase::kVehicleRun, true);

namespace internal {
inline constexpr std::array<Parameter, kCalibrationParameterCount> kCalibrationParametersX =
    Acting<kCalibrationParameterCount>(Phase::kCalibrationTest, false, SensingAxis::kX);
inline constexpr std::array<Parameter, kCalibrationParameterCount> kCalibrationParametersY =
    Acting<kCalibrationParameterCount>(Phase::kCalibrationTest, false, SensingAxis::kY);
inline constexpr std::array<Parameter, kRunParameterCount> kRunParameters =
    Acting<kRunParameterCount>(Phase::kVehicleRun, true, SensingAxis::kX);
}  // namespace internal

// Computed once, at compile time: a joint problem asks for them once per residual.
constexpr const std::array<Parameter, kCalibrationParameterCount>& CalibrationParameters(
    SensingAxis axis) {
  return axis == SensingAxis::kX ? internal::kCalibrationParametersX
                                 : internal::kCalibrationParametersY;
}
constexpr const std::array<Parameter, kRunParameterCount>& RunParameters() {
  return internal::kRunParameters;
}

// A value for every parameter of the catalogue, each at its neutral value unless set.
template <typename T>
class ModelParameters {
 public:
  ModelParameters() {
    for (int i = 0; i < kParameterCount; ++i) values_[i] = T(EffectOf(Parameter(i)).neutral);
  }

  T& operator[](Parameter parameter) { return values_[parameter.index()]; }
  const T& operator[](Parameter parameter) const { return values_[parameter.index()]; }

  // The value of `Effect` for `axis` (its one value when it is shared).
  template <typename Effect>
  const T& Of(SensingAxis axis = SensingAxis::kX) const {
    // Both places are compile-time constants; only the choice between them is not.
    constexpr Parameter x = ParameterOf<Effect>(SensingAxis::kX);
    constexpr Parameter y = ParameterOf<Effect>(SensingAxis::kY);
    static_assert(x.index() >= 0 && y.index() >= 0, "a registered effect has a place");
    return values_[(axis == SensingAxis::kX ? x : y).index()];
  }

 private:
  std::array<T, kParameterCount> values_;
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_H_
