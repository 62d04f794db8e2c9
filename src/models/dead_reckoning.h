#ifndef ACCELCAL_MODELS_DEAD_RECKONING_H_
#define ACCELCAL_MODELS_DEAD_RECKONING_H_

// Dead reckoning by the trapezoidal rule (../shared/spec/error-model.md, "Vehicle run and
// dead reckoning"), per axis, with samples uniformly spaced by dt:
//
//   v_j = v_{j-1} + dt/2 (a_j + a_{j-1})          [m/s]
//   p_j = p_{j-1} + dt/2 (v_j + v_{j-1})          [m]
//
// The endpoint is linear in the accelerations, p_end = p0 + v0 T + sum_j w_j a_j;
// EndpointWeights gives the w_j exactly (the adjoint of the recursion), so the run's
// white noise contributes sum_j w_j^2 sigma^2 to the endpoint variance.
// Templated so the same step runs in double and in ceres::Jet (for exact Jacobians).

#include <vector>

namespace accelcal {

// One axis's position and velocity.
template <typename T>
struct AxisKinematics {
  T position;  // m
  T velocity;  // m/s
};

// Advances `state` by one sample: from acceleration a_{j-1} to a_j.
template <typename T>
void TrapezoidalStep(double dt_s, const T& previous_acceleration, const T& acceleration,
                     AxisKinematics<T>* state) {
  const T half_dt(0.5 * dt_s);
  const T velocity = state->velocity + half_dt * (previous_acceleration + acceleration);
  state->position += half_dt * (state->velocity + velocity);
  state->velocity = velocity;
}

// w_j = d p_end / d a_j for `count` samples. Backward pass: lambda_j = d p_end / d v_j
// (through every later position) is dt/2 for the last sample and grows by dt per sample
// before it; a_j enters v_j and v_{j+1}, each with weight dt/2.
inline std::vector<double> EndpointWeights(int count, double dt_s) {
  std::vector<double> weights(count > 0 ? count : 0, 0.0);
  if (count < 2) return weights;
  std::vector<double> lambda(count, 0.0);
  lambda[count - 1] = 0.5 * dt_s;
  for (int j = count - 2; j >= 1; --j) lambda[j] = lambda[j + 1] + dt_s;
  for (int j = 0; j < count; ++j) {
    const double into_v_j = j >= 1 ? lambda[j] : 0.0;
    const double into_next = j + 1 < count ? lambda[j + 1] : 0.0;
    weights[j] = 0.5 * dt_s * (into_v_j + into_next);
  }
  return weights;
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_DEAD_RECKONING_H_
