#ifndef ACCELCAL_MODELS_TRIAD_EFFECT_H_
#define ACCELCAL_MODELS_TRIAD_EFFECT_H_

// What an effect of the triad (models/triad.h) beyond its 9 parameters is, in code: the
// triad's counterpart of models/effect.h. Each effect is one struct in its own header under
// models/triad_effects/, registered by one line in models/triad_effect_list.h. The struct
// declares
//
//   - kInfo: its name stem, unit, meaning, how many coefficients it has (one, or one per
//     axis: <name>_x, _y, _z), whether static poses can determine it at all (and what it is
//     confounded with when they cannot), and a size at which it is plainly visible; and
//   - Apply(coefficients, context, terms): its term in the model, a change to the pieces
//     below that is zero when its coefficients are.
//
// The prediction of a pose's raw output that the pieces compose (TriadPredictOutput in
// models/triad_effect_list.h), for a unit gravity direction n (sensor frame) at time t:
//
//   f = gravity n                                     specific force          [m/s^2]
//   w = frame^-1 f                                    force along each axis   [m/s^2]
//   u_k = offset_k + (w_k + quadratic_k w_k^2) / gain_k + output_shift_k   [the log's unit]
//
// starting from gravity = g (the stated value), frame = T (models/triad.h), quadratic = 0
// and output_shift = 0: the 9-parameter triad. Everything else (the parameter block, the
// names in the outputs, discovery's candidates, the simulator's truth) follows from the
// registration.

#include <array>

namespace accelcal {

template <typename T>
struct TriadPoseTerms {
  T gravity;                              // m/s^2
  std::array<std::array<T, 3>, 3> frame;  // a = frame w; starts as T
  std::array<T, 3> quadratic;             // 1/(m/s^2), per axis
  std::array<T, 3> output_shift;          // the log's unit, per axis
};

// What an effect may depend on besides its coefficients.
struct TriadPoseContext {
  double time_s = 0.0;  // the pose's mid-time minus the fit's time origin (s)
};

struct TriadEffectInfo {
  const char* name;     // a per-axis effect's stem: its coefficients are <name>_x, _y, _z
  const char* unit;     // "{unit}" stands for the log's unit (count, m/s^2 or g)
  const char* meaning;  // "{axis}" stands for x, y or z in a per-axis effect's text
  int coefficients;     // 1 (one value) or 3 (one per axis)
  // Appended to the stem to name each coefficient: "" for one value, "_x", "_y", "_z" per axis.
  std::array<const char*, 3> suffixes;
  // Empty when static poses of unknown direction can determine it; otherwise what absorbs
  // it exactly, so that it is reported as untestable instead of scored.
  const char* confounded_with;
  // A size at which it is plainly visible in an Xsens-like session (the simulator's
  // demonstration knob and the power tests').
  double example_size;
  // Null for a property of the sensor, which a calibration file carries and `apply` applies to
  // any log; otherwise why it belongs to the session it was found in (a change over the
  // session's time, the lab's gravity): the file still carries it, `apply` leaves it out and
  // says so.
  const char* session_only = nullptr;
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_EFFECT_H_
