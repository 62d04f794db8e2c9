#ifndef ACCELCAL_MODELS_GYROSCOPE_EFFECT_LIST_H_
#define ACCELCAL_MODELS_GYROSCOPE_EFFECT_LIST_H_

// The registration of the gyroscope's effects (models/gyroscope_effect.h), one line each, and what
// follows from it: one block of coefficients (kGyroscopeEffectCoefficientCount doubles, the
// effects in registration order, each effect's coefficients in its suffixes' order), their names
// and units, the calibrated rate with any of them (GyroscopeCorrectedRate) and its inverse, what
// the gyroscope reads at a rate (GyroscopeRawWithEffects).
//
// A build may register more effects without editing this file: configure with
// -DACCELCAL_EXTRA_GYROSCOPE_EFFECTS_HEADER=path/to/header.h, a header that defines
// `using GyroscopeEffects = AppendGyroscopeEffects<BuiltInGyroscopeEffects, MyEffect>::Type;`
// (docs/extending.md; tests/extension/ builds the library that way). The ML fit, its residuals,
// the simulator, discovery's candidates, the calibration file and the studies follow from the
// registration.

#ifdef ACCELCAL_REGISTRY_INDEPENDENT
#error \
    "a source of accelcal_core includes the gyroscope's effects registry: move it to accelcal_add_library's sources (src/CMakeLists.txt)"
#endif

#include <array>
#include <cmath>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "models/gyroscope.h"
#include "models/gyroscope_effect.h"
#include "models/gyroscope_effects/earth_rate.h"
#include "models/gyroscope_effects/g_sensitivity.h"
#include "models/gyroscope_effects/scale_asymmetry.h"
#include "models/gyroscope_effects/scale_nonlinearity.h"
#include "models/gyroscope_effects/time_offset.h"

namespace accelcal {

using BuiltInGyroscopeEffects = std::tuple<GyroscopeGSensitivityEffect,       //
                                           GyroscopeScaleAsymmetryEffect,     //
                                           GyroscopeScaleNonlinearityEffect,  //
                                           GyroscopeTimeOffsetEffect,         //
                                           GyroscopeEarthRateEffect>;

// The built-in effects and more, in order (for ACCELCAL_EXTRA_GYROSCOPE_EFFECTS_HEADER).
template <typename List, typename... More>
struct AppendGyroscopeEffects;
template <typename... Effects, typename... More>
struct AppendGyroscopeEffects<std::tuple<Effects...>, More...> {
  using Type = std::tuple<Effects..., More...>;
};

}  // namespace accelcal

#ifdef ACCELCAL_EXTRA_GYROSCOPE_EFFECTS_HEADER
#include ACCELCAL_EXTRA_GYROSCOPE_EFFECTS_HEADER
#else
namespace accelcal {
using GyroscopeEffects = BuiltInGyroscopeEffects;
}  // namespace accelcal
#endif

namespace accelcal {

constexpr int kGyroscopeEffectCount = std::tuple_size<GyroscopeEffects>::value;

namespace gyroscope_effect_internal {
template <size_t... I>
constexpr int CoefficientCount(std::index_sequence<I...>) {
  return (0 + ... + std::tuple_element_t<I, GyroscopeEffects>::kInfo.coefficients);
}
template <size_t... I>
constexpr std::array<GyroscopeEffectInfo, kGyroscopeEffectCount> Infos(std::index_sequence<I...>) {
  return {std::tuple_element_t<I, GyroscopeEffects>::kInfo...};
}
}  // namespace gyroscope_effect_internal

constexpr int kGyroscopeEffectCoefficientCount =
    gyroscope_effect_internal::CoefficientCount(std::make_index_sequence<kGyroscopeEffectCount>());

using GyroscopeEffectCoefficients = std::array<double, kGyroscopeEffectCoefficientCount>;

// The registered effects' infos, in registration order.
inline const std::array<GyroscopeEffectInfo, kGyroscopeEffectCount>& GyroscopeEffectInfos() {
  static constexpr std::array<GyroscopeEffectInfo, kGyroscopeEffectCount> kInfos =
      gyroscope_effect_internal::Infos(std::make_index_sequence<kGyroscopeEffectCount>());
  return kInfos;
}

// The first coefficient of a registered effect in the block, at compile time:
// GyroscopeEffectFirstOf<GyroscopeGSensitivityEffect>().
template <typename Effect, size_t I = 0>
constexpr int GyroscopeEffectFirstOf() {
  static_assert(I < kGyroscopeEffectCount, "the effect is not registered");
  if constexpr (std::is_same_v<std::tuple_element_t<I, GyroscopeEffects>, Effect>) {
    return 0;
  } else {
    return std::tuple_element_t<I, GyroscopeEffects>::kInfo.coefficients +
           GyroscopeEffectFirstOf<Effect, I + 1>();
  }
}

// The first coefficient of effect `e` (an index into GyroscopeEffectInfos()).
inline int GyroscopeEffectFirst(int e) {
  int first = 0;
  for (int i = 0; i < e; ++i) first += GyroscopeEffectInfos()[i].coefficients;
  return first;
}

// The effect coefficient c belongs to, and its place within it.
inline int GyroscopeEffectOf(int c) {
  for (int e = 0; e < kGyroscopeEffectCount; ++e) {
    if (c < GyroscopeEffectInfos()[e].coefficients) return e;
    c -= GyroscopeEffectInfos()[e].coefficients;
  }
  return -1;
}
inline int GyroscopeEffectPlaceOf(int c) { return c - GyroscopeEffectFirst(GyroscopeEffectOf(c)); }

// The index of the effect named `name` ("g_sensitivity"), -1 when none is.
inline int GyroscopeEffectIndex(const std::string& name) {
  for (int e = 0; e < kGyroscopeEffectCount; ++e)
    if (name == GyroscopeEffectInfos()[e].name) return e;
  return -1;
}

// The name of coefficient c: gyroscope_g_sensitivity_xy, gyroscope_scale_asymmetry_x, ...
inline std::string GyroscopeEffectCoefficientName(int c) {
  const GyroscopeEffectInfo& info = GyroscopeEffectInfos()[GyroscopeEffectOf(c)];
  return std::string("gyroscope_") + info.name + info.suffixes[GyroscopeEffectPlaceOf(c)];
}

inline const char* GyroscopeEffectCoefficientUnit(int c) {
  return GyroscopeEffectInfos()[GyroscopeEffectOf(c)].unit;
}

// The index of the coefficient named `name` (GyroscopeEffectCoefficientName), -1 when none is.
inline int GyroscopeEffectCoefficientIndex(const std::string& name) {
  for (int c = 0; c < kGyroscopeEffectCoefficientCount; ++c)
    if (GyroscopeEffectCoefficientName(c) == name) return c;
  return -1;
}

// Adds the terms of the registered effects of one stage (models/gyroscope_effect.h) to `terms`.
template <GyroscopeEffectStage kStage, typename T>
void ApplyGyroscopeEffects(const T* effects, const GyroscopeSampleContext<T>& context,
                           GyroscopeRateTerms<T>* terms) {
  int first = 0;
  std::apply(
      [&](auto... effect) {
        ((decltype(effect)::kInfo.stage == kStage
              ? decltype(effect)::Apply(effects + first, context, terms)
              : void(),
          first += decltype(effect)::kInfo.coefficients),
         ...);
      },
      GyroscopeEffects{});
}

// Whether any coefficient of a stage's effects is nonzero.
template <typename T>
bool GyroscopeStageActive(const T* effects, GyroscopeEffectStage stage) {
  if (effects == nullptr) return false;
  int first = 0;
  for (const GyroscopeEffectInfo& info : GyroscopeEffectInfos()) {
    if (info.stage == stage)
      for (int c = first; c < first + info.coefficients; ++c)
        if (effects[c] != T(0.0)) return true;
    first += info.coefficients;
  }
  return false;
}

// The composition's terms at a sample (u: its output), through v' (`terms->per_axis` added to
// `terms->along` is v'). `effects` may be null (all coefficients 0).
template <typename T>
void GyroscopeRateTermsAt(const T* parameters, const T* offset, const T* effects, const double* raw,
                          const GyroscopeSampleContext<T>& context, GyroscopeRateTerms<T>* terms) {
  for (int k = 0; k < 3; ++k)
    terms->output_shift[k] = terms->per_axis[k] = terms->rate_shift[k] = T(0.0);
  if (effects != nullptr)
    ApplyGyroscopeEffects<GyroscopeEffectStage::kOutput>(effects, context, terms);
  for (int k = 0; k < 3; ++k) {
    terms->along[k] =
        parameters[kGyroscopeGainX + k] * (T(raw[k]) + terms->output_shift[k] - offset[k]);
  }
  if (effects != nullptr) {
    ApplyGyroscopeEffects<GyroscopeEffectStage::kAxis>(effects, context, terms);
    ApplyGyroscopeEffects<GyroscopeEffectStage::kRate>(effects, context, terms);
  }
}

// w (rad/s) from the output u (counts or the log's unit) and the sample's context, the
// composition of models/gyroscope_effect.h. `effects` may be null (all coefficients 0).
template <typename T>
void GyroscopeCorrectedRate(const T* parameters, const T* offset, const T* effects,
                            const double* raw, const GyroscopeSampleContext<T>& context, T* rate) {
  GyroscopeRateTerms<T> terms;
  GyroscopeRateTermsAt(parameters, offset, effects, raw, context, &terms);
  T primed[3];
  for (int k = 0; k < 3; ++k) primed[k] = terms.along[k] + terms.per_axis[k];
  T m[9];
  GyroscopeMisalignmentMatrix(parameters, m);
  for (int row = 0; row < 3; ++row) {
    rate[row] = m[3 * row] * primed[0] + m[3 * row + 1] * primed[1] + m[3 * row + 2] * primed[2] +
                terms.rate_shift[row];
  }
}

// The same with the specific force f (m/s^2) as the whole context (the output's change 0).
template <typename T>
void GyroscopeCorrectedRate(const T* parameters, const T* offset, const T* effects,
                            const double* raw, const double* specific_force, T* rate) {
  GyroscopeSampleContext<double> context;
  context.specific_force = specific_force;
  const GyroscopeContextAs<T> as(context);
  GyroscopeCorrectedRate(parameters, offset, effects, raw, as.context, rate);
}

// The inverse: the output u at the rate w (rad/s) and the sample's context, what a gyroscope with
// these effects reads (the simulator's direction, and the rest's prediction). v' = T^-1 (w -
// rate_shift); v from v' by fixed-point iteration (the kAxis terms are small: each step gains
// their slope's factor); u = v / gain + b - output_shift.
template <typename T>
void GyroscopeRawWithEffects(const T* parameters, const T* offset, const T* effects, const T* rate,
                             const GyroscopeSampleContext<T>& context, T* raw) {
  GyroscopeRateTerms<T> terms;
  for (int k = 0; k < 3; ++k)
    terms.output_shift[k] = terms.per_axis[k] = terms.rate_shift[k] = T(0.0);
  T sensed[3];
  if (effects != nullptr)
    ApplyGyroscopeEffects<GyroscopeEffectStage::kRate>(effects, context, &terms);
  for (int row = 0; row < 3; ++row) sensed[row] = rate[row] - terms.rate_shift[row];
  // v' = T^-1 (w - rate_shift): GyroscopeRawOutput with gains 1 and offset 0 gives T^-1 x.
  T unit_gains[kGyroscopeParameterCount];
  for (int i = 0; i < kGyroscopeParameterCount; ++i) unit_gains[i] = parameters[i];
  for (int k = 0; k < 3; ++k) unit_gains[kGyroscopeGainX + k] = T(1.0);
  const T zero[3] = {T(0.0), T(0.0), T(0.0)};
  T primed[3];
  GyroscopeRawOutput(unit_gains, zero, sensed, primed);
  for (int k = 0; k < 3; ++k) terms.along[k] = primed[k];
  if (GyroscopeStageActive(effects, GyroscopeEffectStage::kAxis)) {
    for (int step = 0; step < 60; ++step) {
      for (int k = 0; k < 3; ++k) terms.per_axis[k] = T(0.0);
      ApplyGyroscopeEffects<GyroscopeEffectStage::kAxis>(effects, context, &terms);
      bool settled = true;
      for (int k = 0; k < 3; ++k) {
        const T next = primed[k] - terms.per_axis[k];
        settled = settled && next == terms.along[k];
        terms.along[k] = next;
      }
      if (settled) break;
    }
  }
  if (effects != nullptr)
    ApplyGyroscopeEffects<GyroscopeEffectStage::kOutput>(effects, context, &terms);
  for (int k = 0; k < 3; ++k) {
    raw[k] = terms.along[k] / parameters[kGyroscopeGainX + k] + offset[k] - terms.output_shift[k];
  }
}

// The same with the specific force (m/s^2) as the whole context.
template <typename T>
void GyroscopeRawWithEffects(const T* parameters, const T* offset, const T* effects, const T* rate,
                             const T* specific_force, T* raw) {
  GyroscopeSampleContext<T> context;
  context.specific_force = specific_force;
  GyroscopeRawWithEffects(parameters, offset, effects, rate, context, raw);
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_EFFECT_LIST_H_
