#ifndef ACCELCAL_MODELS_TRIAD_EFFECT_LIST_H_
#define ACCELCAL_MODELS_TRIAD_EFFECT_LIST_H_

// The registration of the triad's effects (models/triad_effect.h), one line each, and what
// follows from it: one block of coefficients (kTriadEffectCoefficientCount doubles, the
// effects in registration order, each effect's coefficients in its suffixes' order), their
// names and units, and the prediction of a pose's raw output with any of them.
//
// A build may register more effects without editing this file: configure with
// -DACCELCAL_EXTRA_TRIAD_EFFECTS_HEADER=path/to/header.h, a header that defines
// `using TriadEffects = AppendTriadEffects<BuiltInTriadEffects, MyEffect>::Type;`
// (docs/extending.md; tests/extension/ builds the library that way). The ML fit, the
// simulator, the residual and discovery's candidates follow from the registration.

#ifdef ACCELCAL_REGISTRY_INDEPENDENT
#error \
    "a source of accelcal_core includes the triad's effects registry: move it to accelcal_add_library's sources (src/CMakeLists.txt)"
#endif

#include <array>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "models/triad.h"
#include "models/triad_effect.h"
#include "models/triad_effects/cross_axis.h"
#include "models/triad_effects/gravity_error.h"
#include "models/triad_effects/offset_drift.h"
#include "models/triad_effects/scale_nonlinearity.h"

namespace accelcal {

using BuiltInTriadEffects = std::tuple<TriadScaleNonlinearityEffect,  //
                                       TriadOffsetDriftEffect,        //
                                       TriadGravityErrorEffect,       //
                                       TriadCrossAxisEffect>;

// The built-in effects and more, in order (for ACCELCAL_EXTRA_TRIAD_EFFECTS_HEADER).
template <typename List, typename... More>
struct AppendTriadEffects;
template <typename... Effects, typename... More>
struct AppendTriadEffects<std::tuple<Effects...>, More...> {
  using Type = std::tuple<Effects..., More...>;
};

}  // namespace accelcal

#ifdef ACCELCAL_EXTRA_TRIAD_EFFECTS_HEADER
#include ACCELCAL_EXTRA_TRIAD_EFFECTS_HEADER
#else
namespace accelcal {
using TriadEffects = BuiltInTriadEffects;
}  // namespace accelcal
#endif

namespace accelcal {

constexpr int kTriadEffectCount = std::tuple_size<TriadEffects>::value;

namespace triad_effect_internal {
template <size_t... I>
constexpr int CoefficientCount(std::index_sequence<I...>) {
  return (0 + ... + std::tuple_element_t<I, TriadEffects>::kInfo.coefficients);
}
template <size_t... I>
constexpr std::array<TriadEffectInfo, kTriadEffectCount> Infos(std::index_sequence<I...>) {
  return {std::tuple_element_t<I, TriadEffects>::kInfo...};
}
}  // namespace triad_effect_internal

constexpr int kTriadEffectCoefficientCount =
    triad_effect_internal::CoefficientCount(std::make_index_sequence<kTriadEffectCount>());

using TriadEffectCoefficients = std::array<double, kTriadEffectCoefficientCount>;

// The registered effects' infos, in registration order.
inline const std::array<TriadEffectInfo, kTriadEffectCount>& TriadEffectInfos() {
  static constexpr std::array<TriadEffectInfo, kTriadEffectCount> kInfos =
      triad_effect_internal::Infos(std::make_index_sequence<kTriadEffectCount>());
  return kInfos;
}

// One coefficient of the block: its effect and its full name ("offset_drift_x").
struct TriadEffectCoefficient {
  int effect = 0;  // index into TriadEffectInfos()
  int axis = 0;    // index into the effect's suffixes
  std::string name;
};
inline std::vector<TriadEffectCoefficient> TriadEffectCoefficientList() {
  std::vector<TriadEffectCoefficient> list;
  const auto infos = TriadEffectInfos();
  for (int e = 0; e < kTriadEffectCount; ++e) {
    for (int k = 0; k < infos[e].coefficients; ++k)
      list.push_back({e, k, std::string(infos[e].name) + infos[e].suffixes[k]});
  }
  return list;
}

// The index of a coefficient in the block by its name, -1 when none has it.
inline int TriadEffectCoefficientIndex(const std::string& name) {
  const std::vector<TriadEffectCoefficient> list = TriadEffectCoefficientList();
  for (size_t i = 0; i < list.size(); ++i)
    if (list[i].name == name) return static_cast<int>(i);
  return -1;
}

// The unit of a coefficient, with "{unit}" replaced by the log's unit.
inline std::string TriadEffectUnit(int coefficient, const std::string& log_unit) {
  std::string unit = TriadEffectInfos()[TriadEffectCoefficientList()[coefficient].effect].unit;
  const size_t at = unit.find("{unit}");
  if (at != std::string::npos) unit.replace(at, 6, log_unit);
  return unit;
}

// The raw output (the log's unit) predicted for a pose of unit gravity direction n under the
// stated gravity g (m/s^2), models/triad_effect.h's composition. `effects` may be null (the
// 9-parameter triad, exactly TriadRawOutput). Returns false when the frame is singular.
template <typename T>
bool TriadPredictOutput(const T* parameters, const T* effects, const TriadPoseContext& context,
                        const T* direction, double gravity_mps2, T* raw) {
  if (effects == nullptr) {
    const T force[3] = {T(gravity_mps2) * direction[0], T(gravity_mps2) * direction[1],
                        T(gravity_mps2) * direction[2]};
    TriadRawOutput(parameters, force, raw);
    return true;
  }
  TriadPoseTerms<T> terms;
  terms.gravity = T(gravity_mps2);
  for (auto& row : terms.frame) row.fill(T(0.0));
  for (int k = 0; k < 3; ++k) terms.frame[k][k] = T(1.0);
  terms.frame[0][1] = -parameters[kTriadMisalignmentYz];
  terms.frame[0][2] = parameters[kTriadMisalignmentZy];
  terms.frame[1][2] = -parameters[kTriadMisalignmentZx];
  terms.quadratic.fill(T(0.0));
  terms.output_shift.fill(T(0.0));
  int offset = 0;
  std::apply(
      [&](auto... effect) {
        ((decltype(effect)::Apply(effects + offset, context, &terms),
          offset += decltype(effect)::kInfo.coefficients),
         ...);
      },
      TriadEffects{});
  const T f[3] = {terms.gravity * direction[0], terms.gravity * direction[1],
                  terms.gravity * direction[2]};
  // w = frame^-1 f by Cramer's rule (the frame is near the identity).
  const auto& m = terms.frame;
  const T det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  if (!(det != T(0.0))) return false;
  T w[3];
  for (int c = 0; c < 3; ++c) {
    T column[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) column[i][j] = j == c ? f[i] : m[i][j];
    w[c] = (column[0][0] * (column[1][1] * column[2][2] - column[1][2] * column[2][1]) -
            column[0][1] * (column[1][0] * column[2][2] - column[1][2] * column[2][0]) +
            column[0][2] * (column[1][0] * column[2][1] - column[1][1] * column[2][0])) /
           det;
  }
  for (int k = 0; k < 3; ++k) {
    raw[k] = parameters[kTriadOffsetX + k] +
             (w[k] + terms.quadratic[k] * w[k] * w[k]) / parameters[kTriadGainX + k] +
             terms.output_shift[k];
  }
  return true;
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_EFFECT_LIST_H_
