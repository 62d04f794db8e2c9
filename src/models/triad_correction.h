#ifndef ACCELCAL_MODELS_TRIAD_CORRECTION_H_
#define ACCELCAL_MODELS_TRIAD_CORRECTION_H_

// A triad's calibration as a correction applies it: the 9 parameters (models/triad.h) and the
// effect coefficients (models/triad_effect_list.h) of the model discovery settled on, from the
// raw output u back to the specific force f. With no effect term it is a = T K (u - b)
// (TriadSpecificForce); with some, f is the force whose predicted output (TriadPredictOutput,
// at the session's mean time) is u, solved by fixed-point steps from the 9-parameter correction:
//
//   f_0 = T K (u - b),   f_{i+1} = f_i + T K (u - predicted(f_i)),
//
// which contract by about the effect terms' relative size (2 k2 |w| for a second-order scale
// term: 4e-3 at 1 g for the largest seen on MEMS accelerometers), so that a few of them reach
// double precision (they stop three steps after that, at most kTriadCorrectionMaxSteps), and
// ceres::Jets carried through them give the correction's derivatives (its covariance,
// estimation/tilt_table/ calibration_correction.h). Only the effects that are properties of the
// sensor are applied (TriadEffectInfo::session_only null); the others are carried in the file and
// named.

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "models/triad.h"
#include "models/triad_effect_list.h"
#include "models/triad_units.h"

namespace accelcal {

struct TriadCalibrationModel {
  TriadParameters parameters{};
  // The effect coefficients a correction applies; 0 for those the calibration does not carry
  // and for session-only ones.
  TriadEffectCoefficients effects{};
  std::vector<int> effects_applied;  // indices into the block, in its order
  // Carried by the calibration but not applied: indices into the block.
  std::vector<int> effects_not_applied;
  // (kTriadParameterCount + kTriadEffectCoefficientCount) square: the 9, then the block; rows and
  // columns of coefficients not applied are 0.
  Eigen::MatrixXd covariance;
  TriadOutputUnit unit = TriadOutputUnit::kCount;
  double gravity_mps2 = 9.8;

  bool has_effects() const { return !effects_applied.empty(); }
};

// The most fixed-point steps: a contraction of 0.5 per step (a term a hundred times the largest
// seen) settles within 60.
constexpr int kTriadCorrectionMaxSteps = 100;
constexpr int kTriadCorrectionUnknowns = kTriadParameterCount + kTriadEffectCoefficientCount;

// Whether coefficient c of the block is applied by a correction (its effect is a property of
// the sensor).
inline bool TriadEffectAppliedInUse(int coefficient) {
  return TriadEffectInfos()[TriadEffectCoefficientList()[coefficient].effect].session_only ==
         nullptr;
}

namespace triad_correction_internal {
// The value of a scalar or of a ceres::Jet (its member a), without including Ceres here.
inline double ScalarPart(double value) { return value; }
template <typename Jet>
double ScalarPart(const Jet& jet) {
  return jet.a;
}
}  // namespace triad_correction_internal

// f (m/s^2) from the raw output `raw` (the calibration's unit) under `parameters` (the 9) and
// `effects` (the block; null: none). Returns false when the steps do not settle (an effect term
// so large that the output has no force near the 9-parameter correction's; no real sensor's).
template <typename T>
bool TriadCorrectedForce(const T* parameters, const T* effects, const double* raw,
                         double gravity_mps2, T* force) {
  TriadSpecificForce(parameters, raw, force);
  if (effects == nullptr) return true;
  const TriadPoseContext at_mean_time;
  double last_step = 0.0;
  int quiet_steps = 0;  // in a row, below rounding's level: the derivatives settle with them
  for (int step = 0; step < kTriadCorrectionMaxSteps && quiet_steps < 3; ++step) {
    T direction[3], predicted[3];
    for (int k = 0; k < 3; ++k) direction[k] = force[k] / T(gravity_mps2);
    if (!TriadPredictOutput(parameters, effects, at_mean_time, direction, gravity_mps2, predicted))
      return false;
    // T K (u - predicted): TriadSpecificForce's linear part on the output's difference.
    T along[3];
    for (int k = 0; k < 3; ++k) along[k] = parameters[kTriadGainX + k] * (T(raw[k]) - predicted[k]);
    const T change[3] = {along[0] - parameters[kTriadMisalignmentYz] * along[1] +
                             parameters[kTriadMisalignmentZy] * along[2],
                         along[1] - parameters[kTriadMisalignmentZx] * along[2], along[2]};
    last_step = 0.0;
    for (int k = 0; k < 3; ++k) {
      force[k] += change[k];
      last_step = std::max(last_step, std::abs(triad_correction_internal::ScalarPart(change[k])));
    }
    quiet_steps = last_step <= 1e-13 * gravity_mps2 ? quiet_steps + 1 : 0;
  }
  // Settled: the last step is at rounding's level of the force.
  return last_step <= 1e-9 * gravity_mps2;
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_CORRECTION_H_
