#ifndef ACCELCAL_MODELS_GYROSCOPE_EFFECT_H_
#define ACCELCAL_MODELS_GYROSCOPE_EFFECT_H_

// What an effect of the gyroscope (models/gyroscope.h) beyond its 9 parameters and offset is, in
// code: the gyroscope's counterpart of models/triad_effect.h. Each effect is one struct in its own
// header under models/gyroscope_effects/, registered by one line in
// models/gyroscope_effect_list.h. The struct declares
//
//   - kInfo: its name, unit, meaning, coefficients and their suffixes, the stage of the
//     correction it acts in, what determines it, and example values (the simulator's
//     demonstration and the studies' truth); and
//   - Apply(coefficients, context, terms): its term, a change to the stage's piece below that is
//     zero when its coefficients are.
//
// The calibrated rate w (rad/s, the accelerometer's frame) of a sample's output u (counts or the
// log's unit) composes the stages in order, each effect's term added in its stage:
//
//   u'_k = u_k + output_shift_k                    kOutput: the output itself (the log's unit)
//   v_k  = gain_k (u'_k - b_k)                      (rad/s along sensing axis k)
//   v'_k = v_k + per_axis_k                         kAxis: may depend on v (rad/s)
//   w    = T v' + rate_shift                        kRate: in the frame (rad/s)
//
// starting from output_shift = 0, per_axis = 0 and rate_shift = 0: models/gyroscope.h's model.
// A kOutput or kRate term may depend on the sample's context (its specific force, the output's
// change in time) but not on v; a kAxis term on v (and the context). The simulator inverts the
// composition (GyroscopeRawWithEffects), the residuals differentiate it, `apply` applies it;
// the parameter block, the names in the outputs, discovery's candidates, the calibration file's
// terms and the studies' truth follow from the registration.

#include <array>
#include <vector>

namespace accelcal {

// Where an effect's term enters the correction (above).
enum class GyroscopeEffectStage { kOutput, kAxis, kRate };

// What a sample's term may depend on besides the coefficients and v (T: the coefficients' type;
// the rest's prediction differentiates the force too).
template <typename T>
struct GyroscopeSampleContext {
  // The specific force the calibrated accelerometer measures at the sample (m/s^2, its frame).
  const T* specific_force = nullptr;
  // The output's rate of change at the sample (the log's unit per s; central differences of the
  // samples around it); null: 0, as at rest.
  const T* output_rate = nullptr;
};

// Uninitialised, as a double array is: whoever composes sets the pieces to 0 first (a
// ceres::Jet's default is already 0 with 0 derivatives).
template <typename T>
struct GyroscopeRateTerms {
  std::array<T, 3> output_shift;  // kOutput: added to u (the log's unit)
  std::array<T, 3> along;         // v, read by kAxis terms
  std::array<T, 3> per_axis;      // kAxis: added to v (rad/s)
  std::array<T, 3> rate_shift;    // kRate: added to T v' (rad/s)
};

// A context of doubles as constants of another scalar type (a ceres::Jet), held with their
// values: `context` points into this object, which is therefore neither copied nor moved.
template <typename T>
struct GyroscopeContextAs {
  explicit GyroscopeContextAs(const GyroscopeSampleContext<double>& of) {
    for (int k = 0; k < 3; ++k) {
      force[k] = T(of.specific_force == nullptr ? 0.0 : of.specific_force[k]);
      output_rate[k] = T(of.output_rate == nullptr ? 0.0 : of.output_rate[k]);
    }
    context.specific_force = force;
    context.output_rate = output_rate;
  }
  GyroscopeContextAs(const GyroscopeContextAs&) = delete;
  GyroscopeContextAs& operator=(const GyroscopeContextAs&) = delete;

  T force[3];
  T output_rate[3];
  GyroscopeSampleContext<T> context;
};

// The output's rate of change at sample i (the outputs' unit per s): central differences over
// the samples around it, one-sided at the ends, 0 where the times do not advance. The context's
// output_rate wherever a log's samples are at hand (the fit's turns and poses, the simulator).
inline std::array<double, 3> GyroscopeOutputRate(const std::vector<double>& times_s,
                                                 const std::vector<std::array<double, 3>>& outputs,
                                                 int i) {
  const int lo = i > 0 ? i - 1 : 0;
  const int hi = i + 1 < static_cast<int>(outputs.size()) ? i + 1 : i;
  const double span = times_s[hi] - times_s[lo];
  std::array<double, 3> rate{};
  if (span > 0.0)
    for (int k = 0; k < 3; ++k) rate[k] = (outputs[hi][k] - outputs[lo][k]) / span;
  return rate;
}

struct GyroscopeEffectInfo {
  const char* name;  // the group's name in outputs; its coefficients are gyroscope_<name><suffix>
  const char* unit;  // its coefficients' unit
  const char* meaning;     // in a user's words
  const char* suggestion;  // what a user can do when it is found
  int coefficients;        // 1 to 9
  // Appended to gyroscope_<name> to name each coefficient: "" for one value, "_x" .. per axis,
  // "_xy" .. per entry of a matrix.
  std::array<const char*, 9> suffixes;
  GyroscopeEffectStage stage;
  // Whether the poses at rest see it (their means shift with it: the rest residuals determine
  // it), or only the turns do.
  bool seen_at_rest;
  // Whether coefficient k (k < 3) belongs to sensing axis k, so that turns about that axis
  // determine it (a per-axis effect); false for terms of the whole frame.
  bool per_axis;
  // The values the simulator's demonstration and the studies' --effects put in (one per
  // coefficient): plainly visible in gyroscope_study's design.
  std::array<double, 9> example;
  // Null for a property of the sensor, which a calibration file carries and `apply` applies;
  // otherwise why it belongs to the session it was found in: the file carries it, `apply` leaves
  // it out and says so.
  const char* session_only = nullptr;
  // Null for an effect of the sensor, one of discovery's candidates; otherwise why it is not one:
  // a rate of the world every session sees, which the fit holds in every model (known, or
  // bounded by its prior) and discovery never names (models/gyroscope_effects/earth_rate.h).
  const char* not_a_candidate = nullptr;
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_EFFECT_H_
