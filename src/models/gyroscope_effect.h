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

template <typename T>
struct GyroscopeRateTerms {
  std::array<T, 3> output_shift;  // kOutput: added to u (the log's unit)
  std::array<T, 3> along;         // v, read by kAxis terms
  std::array<T, 3> per_axis;      // kAxis: added to v (rad/s)
  std::array<T, 3> rate_shift;    // kRate: added to T v' (rad/s)
};

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
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_EFFECT_H_
