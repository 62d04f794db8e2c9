#ifndef ACCELCAL_MODELS_EFFECT_H_
#define ACCELCAL_MODELS_EFFECT_H_

// What an effect of the catalogue is, in code. Each effect of ../shared/spec/error-model.md
// is one struct in its own header under models/effects/, registered by one line in
// models/effect_list.h. The struct declares
//
//   - kInfo: its output name, unit, meaning, whether it has one value or one per axis, the
//     phases it acts in (tilt test, vehicle run, or both), its neutral value and a size at
//     which it is plainly visible; and
//   - its term in the model, by hiding one or more of the hooks of EffectTerms below.
//
// Everything else follows from the registration: the parameter's place in ModelParameters,
// the Ceres parameter blocks of each residual (an effect acting in the test is a block of
// the tilt-test residuals, one acting in the run a block of the endpoint residual), the
// dead-reckoning Jacobian, the simulator's --set and scenario keys, the joint solver's
// --effects and discovery's candidates. models/sensor_model.h calls the hooks.
//
// The model the hooks compose, for a sample of phase P (tilt test or vehicle run):
//
//   theta_true = CorrectTableAngle(theta_reported)        tilt test only          [rad]
//   (f_along_x, f_along_y) = Project(fx, fy)              linear in the forces    [m/s^2]
//   m_k = c0 + c1 f + c2 f^2 + c3 f^3,  f = f_along_k     c from AddAxisTerms     [m/s^2]
//
// starting from c = (0, 1, 0, 0), i.e. a perfect axis. The hooks of the effects are applied
// in registration order (Unproject in reverse order).

#include <array>
#include <type_traits>

namespace accelcal {

// The two sensing axes; x is the reference axis.
enum class SensingAxis { kX, kY };

// Which part of the experiment a sample belongs to.
enum class Phase { kCalibrationTest, kVehicleRun };

// Where an effect acts. One that acts only in the vehicle run (run_bias_shift_k) is
// observable only through a landmark.
enum class ActsIn { kCalibrationTest, kVehicleRun, kBoth };

// One value for the sensor (angle_offset) or one per axis (bias_x, bias_y).
enum class Scope { kShared, kPerAxis };

// kBaseline: the reference report's model (always estimated). kEffect: an effect the joint
// model may estimate and discovery may name. kNoiseRatio: the ratio of the true noise
// variance to the stated one, read from chi-square rather than estimated by Ceres.
enum class Role { kBaseline, kEffect, kNoiseRatio };

struct EffectInfo {
  const char* name;     // a per-axis effect's stem: its parameters are <name>_x and <name>_y
  const char* unit;     // as in the spec
  const char* meaning;  // "{axis}" stands for x or y in a per-axis effect's text
  Scope scope;
  ActsIn acts_in;
  Role role;
  double neutral;  // the value at which the effect is absent
  // A size at which the effect is plainly visible on the course-sized experiment (the
  // simulator's demonstration knob, used by the coverage and power studies).
  double example_size;
  // The highest power of the force along the axis that AddAxisTerms adds (0 when it adds
  // none). Above 2 the run's inverse is no longer closed-form (see InvertAxisResponse).
  int force_degree;
  // The largest |value - neutral| a scenario or --set may give the effect: beyond it the
  // sensor no longer measures the force it is meant to (a scale of -1, a bias of 10 g) and
  // the simulation would only produce overflow or nonsense. 0: no bound of its own (the
  // scenario checks apply a generic 1e6).
  double largest_deviation = 0.0;
};

constexpr bool ActsInPhase(const EffectInfo& info, Phase phase) {
  return info.acts_in == ActsIn::kBoth ||
         (phase == Phase::kCalibrationTest) == (info.acts_in == ActsIn::kCalibrationTest);
}

// One axis's output as a polynomial in the force f along it [m/s^2]:
//   m = c[0] + c[1] f + c[2] f^2 + c[3] f^3
// (evaluated by models/sensor_model.h, which knows the highest degree registered).
template <typename T>
struct AxisPolynomial {
  std::array<T, 4> c = {T(0.0), T(1.0), T(0.0), T(0.0)};
};

// The hooks an effect may hide; each does nothing here. `value` is the effect's parameter
// (for a per-axis effect in AddAxisTerms, the value of the axis being evaluated). Only
// shared effects may hide CorrectTableAngle, Project and Unproject.
struct EffectTerms {
  // The true table angle from the reported one (tilt test only).
  template <typename T>
  static void CorrectTableAngle(const T& /*value*/, T* /*theta_rad*/) {}
  // The forces along the sensing axes from the frame's; must be linear in the forces (the
  // endpoint residual undoes it once on weighted sums of forces).
  template <typename T>
  static void Project(const T& /*value*/, T* /*along_x*/, T* /*along_y*/) {}
  // The exact inverse of Project.
  template <typename T>
  static void Unproject(const T& /*value*/, T* /*x*/, T* /*y*/) {}
  // Adds the effect's terms to one axis's output polynomial; `drift_coordinate` is u_i of
  // the tilt test (DriftCoordinate), 0 in the vehicle run.
  template <typename T>
  static void AddAxisTerms(const T& /*value*/, double /*drift_coordinate*/,
                           AxisPolynomial<T>* /*output*/) {}
};

// A list of effects: the registration (models/effect_list.h) is one.
template <typename... Effects>
struct EffectList {
  static constexpr int kSize = sizeof...(Effects);
};

// A list with more effects at its end.
template <typename List, typename... More>
struct AppendEffects;
template <typename... Effects, typename... More>
struct AppendEffects<EffectList<Effects...>, More...> {
  using Type = EffectList<Effects..., More...>;
};

// Calls fn(static_cast<Effect*>(nullptr)) for each effect of the list, in order.
template <typename... Effects, typename Fn>
constexpr void ForEachEffectIn(EffectList<Effects...> /*list*/, Fn&& fn) {
  (fn(static_cast<Effects*>(nullptr)), ...);
}

// The same in reverse order (Unproject undoes the projections last-in, first-out).
template <typename Fn>
constexpr void ForEachEffectReversedIn(EffectList<> /*list*/, Fn&& /*fn*/) {}
template <typename First, typename... Rest, typename Fn>
constexpr void ForEachEffectReversedIn(EffectList<First, Rest...> /*list*/, Fn&& fn) {
  ForEachEffectReversedIn(EffectList<Rest...>(), fn);
  fn(static_cast<First*>(nullptr));
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECT_H_
