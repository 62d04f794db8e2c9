#ifndef ACCELCAL_MODELS_SENSOR_MODEL_H_
#define ACCELCAL_MODELS_SENSOR_MODEL_H_

// The accelerometer pair's forward model, exactly as ../shared/spec/error-model.md
// ("Sensor output") defines it, composed from the registered effects' terms
// (models/effect.h, models/effect_list.h). Everything that predicts a sensor output (Ceres
// residuals, the closed-form baseline, the simulator, dead reckoning) calls these
// functions, so they cannot disagree. With the built-in effects each axis k in {x, y}
// outputs [m/s^2]
//
//   m_k = (1 + s_k) f_along_k + k2_k f_along_k^2 + b_k + d_k u_i + r_k + zeta_k
//   f_along_x = fx,  f_along_y = fy cos(eps) + fx sin(eps)
//
// with d_k u_i present only in the calibration test and r_k only in the vehicle run. The
// noise zeta_k is not part of the deterministic prediction; the simulator adds it. The
// baseline model of the reference report is b_k, s_k only (every other term neutral).

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/measurements.h"
#include "models/effects.h"
#include "models/tilt_table.h"

namespace accelcal {

// u_i = i/(N-1) - 0.5 for sample i of N calibration samples, so that the drift term
// has zero mean and b_k stays the mean bias over the test. A single sample has u = 0.
inline double DriftCoordinate(int sample_index, int sample_count) {
  if (sample_count < 2) return 0.0;
  return static_cast<double>(sample_index) / static_cast<double>(sample_count - 1) - 0.5;
}

// The highest power of the force in an axis's output in `phase`, over the registered
// effects: the run's inverse is closed-form up to 2.
constexpr int ForceDegree(Phase phase) {
  int degree = 1;
  for (const EffectInfo& info : kEffectInfos) {
    if (info.role != Role::kNoiseRatio && ActsInPhase(info, phase))
      degree = std::max(degree, info.force_degree);
  }
  return degree;
}

// The highest power of the force any registered effect adds, in either phase.
constexpr int kMaxForceDegree =
    std::max(ForceDegree(Phase::kCalibrationTest), ForceDegree(Phase::kVehicleRun));

// The polynomial's value and slope at the force f. Without a registered cubic term c3 is
// always zero and is left out: these run once per residual evaluation and per run sample.
template <typename T>
T Evaluate(const AxisPolynomial<T>& p, const T& f) {
  if constexpr (kMaxForceDegree > 2) return ((p.c[3] * f + p.c[2]) * f + p.c[1]) * f + p.c[0];
  return (p.c[2] * f + p.c[1]) * f + p.c[0];
}
template <typename T>
T Slope(const AxisPolynomial<T>& p, const T& f) {
  if constexpr (kMaxForceDegree > 2) return (T(3.0) * p.c[3] * f + T(2.0) * p.c[2]) * f + p.c[1];
  return T(2.0) * p.c[2] * f + p.c[1];
}

// The true table angle [rad] from the reported one (tilt test only).
template <typename T>
T TrueTableAngle(const T& theta_reported_rad, const ModelParameters<T>& parameters) {
  T theta = theta_reported_rad;
  ForEachEffectIn(RegisteredEffects(), [&](auto* effect) {
    using Effect = std::remove_pointer_t<decltype(effect)>;
    if constexpr (Effect::kInfo.scope == Scope::kShared &&
                  ActsInPhase(Effect::kInfo, Phase::kCalibrationTest)) {
      Effect::CorrectTableAngle(parameters.template Of<Effect>(), &theta);
    }
  });
  return theta;
}

// Projects the true specific force (reference frame) on the two sensing axes.
template <typename T>
void ProjectOnSensingAxes(const T& specific_force_x, const T& specific_force_y,
                          const ModelParameters<T>& parameters, Phase phase, T* along_x,
                          T* along_y) {
  *along_x = specific_force_x;
  *along_y = specific_force_y;
  ForEachEffectIn(RegisteredEffects(), [&](auto* effect) {
    using Effect = std::remove_pointer_t<decltype(effect)>;
    if constexpr (Effect::kInfo.scope == Scope::kShared) {
      if (ActsInPhase(Effect::kInfo, phase))
        Effect::Project(parameters.template Of<Effect>(), along_x, along_y);
    }
  });
}

// Undoes ProjectOnSensingAxes: the reference-frame force from the forces along the sensing
// axes. Linear in the forces, so it may be applied to weighted sums of them as well as to
// one sample.
template <typename T>
void UndoProjection(const T& along_x, const T& along_y, const ModelParameters<T>& parameters,
                    Phase phase, T* specific_force_x, T* specific_force_y) {
  *specific_force_x = along_x;
  *specific_force_y = along_y;
  ForEachEffectReversedIn(RegisteredEffects(), [&](auto* effect) {
    using Effect = std::remove_pointer_t<decltype(effect)>;
    if constexpr (Effect::kInfo.scope == Scope::kShared) {
      if (ActsInPhase(Effect::kInfo, phase))
        Effect::Unproject(parameters.template Of<Effect>(), specific_force_x, specific_force_y);
    }
  });
}

// One axis's output as a polynomial in the force along it, in `phase`. `drift_coordinate`
// is u_i (DriftCoordinate) in the tilt test and ignored in the vehicle run.
template <typename T>
AxisPolynomial<T> AxisResponse(const ModelParameters<T>& parameters, SensingAxis axis,
                               double drift_coordinate, Phase phase) {
  AxisPolynomial<T> response;
  const double u = phase == Phase::kCalibrationTest ? drift_coordinate : 0.0;
  ForEachEffectIn(RegisteredEffects(), [&](auto* effect) {
    using Effect = std::remove_pointer_t<decltype(effect)>;
    if constexpr (Effect::kInfo.role != Role::kNoiseRatio) {
      if (ActsInPhase(Effect::kInfo, phase))
        Effect::AddAxisTerms(parameters.template Of<Effect>(axis), u, &response);
    }
  });
  return response;
}

// The noiseless output of one axis for the specific force along it.
template <typename T>
T AxisOutput(const T& specific_force_along_axis, const ModelParameters<T>& parameters,
             SensingAxis axis, double drift_coordinate, Phase phase) {
  return Evaluate(AxisResponse(parameters, axis, drift_coordinate, phase),
                  specific_force_along_axis);
}

// The force along the axis that produces the noiseless output `measured`. With
// c = c0 - m the quadratic part is c2 f^2 + c1 f + c = 0; the root that tends to the linear
// inverse -c/c1 as c2 -> 0 is written without cancellation as
// f = -2c / (c1 + sqrt(c1^2 - 4 c2 c)). A negative discriminant (an output no force can
// produce) is clamped at zero. When a registered effect of the run has a cubic term, Newton
// steps from that root follow until they no longer move it (quadratic convergence from a
// root already within about |c3 f^3| of the answer). At least one is taken whatever c3's
// value: a Newton step at the root carries the implicit derivative -(dm/dp)/(dm/df), so
// the derivatives with respect to c3 are exact too, even at c3 = 0.
template <typename T>
T InvertAxisResponse(const AxisPolynomial<T>& response, const T& measured) {
  using std::abs;
  using std::sqrt;
  const T c = response.c[0] - measured;
  T discriminant = response.c[1] * response.c[1] - T(4.0) * response.c[2] * c;
  if (discriminant < T(0.0)) discriminant = T(0.0);
  T force = T(-2.0) * c / (response.c[1] + sqrt(discriminant));
  if constexpr (ForceDegree(Phase::kVehicleRun) > 2) {
    for (int iteration = 0; iteration < 30; ++iteration) {
      const T step = (Evaluate(response, force) - measured) / Slope(response, force);
      force -= step;
      if (!(abs(step) > T(1e-15) * (T(1.0) + abs(force)))) break;
    }
  }
  return force;
}

// The tilt test's force along each sensing axis at the reported angle theta (rad): the
// true angle, the table's force in gravity g (m/s^2) and its projection.
template <typename T>
void CalibrationForcesAlongAxes(double theta_reported_rad, double gravity_mps2,
                                const ModelParameters<T>& parameters, T* along_x, T* along_y) {
  T force_x;
  T force_y;
  TiltTableSpecificForce(TrueTableAngle(T(theta_reported_rad), parameters), gravity_mps2, &force_x,
                         &force_y);
  ProjectOnSensingAxes(force_x, force_y, parameters, Phase::kCalibrationTest, along_x, along_y);
}

// The tilt test's prediction of one axis at the reported angle theta (rad) and drift
// coordinate u.
template <typename T>
T PredictCalibrationOutput(double theta_reported_rad, double drift_coordinate, SensingAxis axis,
                           double gravity_mps2, const ModelParameters<T>& parameters) {
  T along_x;
  T along_y;
  CalibrationForcesAlongAxes(theta_reported_rad, gravity_mps2, parameters, &along_x, &along_y);
  return AxisOutput(axis == SensingAxis::kX ? along_x : along_y, parameters, axis, drift_coordinate,
                    Phase::kCalibrationTest);
}

// Both axes' predictions, from one evaluation of the forces.
template <typename T>
void PredictCalibrationOutputs(double theta_reported_rad, double drift_coordinate,
                               double gravity_mps2, const ModelParameters<T>& parameters,
                               T* output_x, T* output_y) {
  T along_x;
  T along_y;
  CalibrationForcesAlongAxes(theta_reported_rad, gravity_mps2, parameters, &along_x, &along_y);
  *output_x =
      AxisOutput(along_x, parameters, SensingAxis::kX, drift_coordinate, Phase::kCalibrationTest);
  *output_y =
      AxisOutput(along_y, parameters, SensingAxis::kY, drift_coordinate, Phase::kCalibrationTest);
}

// The tilt test's residuals m - prediction (m/s^2) of each axis under `values`.
inline void CalibrationResiduals(const CalibrationTest& test, const ModelParameters<double>& values,
                                 double gravity_mps2, std::vector<double>* residual_x,
                                 std::vector<double>* residual_y) {
  const int n = test.size();
  residual_x->resize(n);
  residual_y->resize(n);
  for (int i = 0; i < n; ++i) {
    double predicted_x;
    double predicted_y;
    PredictCalibrationOutputs(test.theta_rad[i], DriftCoordinate(i, n), gravity_mps2, values,
                              &predicted_x, &predicted_y);
    (*residual_x)[i] = test.measured_x[i] - predicted_x;
    (*residual_y)[i] = test.measured_y[i] - predicted_y;
  }
}

// The vehicle run's correction: each axis's output inverted (InvertAxisResponse), then the
// projection undone (UndoProjection). The axes' responses are formed once, so correcting
// a sample costs two inversions.
template <typename T>
class RunCorrection {
 public:
  explicit RunCorrection(const ModelParameters<T>& parameters)
      : parameters_(parameters),
        response_x_(AxisResponse(parameters, SensingAxis::kX, 0.0, Phase::kVehicleRun)),
        response_y_(AxisResponse(parameters, SensingAxis::kY, 0.0, Phase::kVehicleRun)) {}

  const AxisPolynomial<T>& response(SensingAxis axis) const {
    return axis == SensingAxis::kX ? response_x_ : response_y_;
  }

  // The force along each axis that produced `measured` (before the projection is undone).
  T AlongAxis(const T& measured, SensingAxis axis) const {
    return InvertAxisResponse(response(axis), measured);
  }

  // The frame's force from forces (or weighted sums of them) along the sensing axes.
  void Unproject(const T& along_x, const T& along_y, T* acceleration_x, T* acceleration_y) const {
    UndoProjection(along_x, along_y, parameters_, Phase::kVehicleRun, acceleration_x,
                   acceleration_y);
  }

  // The vehicle's acceleration (reference frame) recovered from one run sample.
  void operator()(const T& measured_x, const T& measured_y, T* acceleration_x,
                  T* acceleration_y) const {
    Unproject(AlongAxis(measured_x, SensingAxis::kX), AlongAxis(measured_y, SensingAxis::kY),
              acceleration_x, acceleration_y);
  }

 private:
  const ModelParameters<T> parameters_;
  const AxisPolynomial<T> response_x_;
  const AxisPolynomial<T> response_y_;
};

// The run's noiseless outputs for the vehicle's true acceleration (reference frame).
template <typename T>
void PredictRunOutputs(const T& acceleration_x, const T& acceleration_y,
                       const ModelParameters<T>& parameters, T* output_x, T* output_y) {
  T along_x;
  T along_y;
  ProjectOnSensingAxes(acceleration_x, acceleration_y, parameters, Phase::kVehicleRun, &along_x,
                       &along_y);
  *output_x = AxisOutput(along_x, parameters, SensingAxis::kX, 0.0, Phase::kVehicleRun);
  *output_y = AxisOutput(along_y, parameters, SensingAxis::kY, 0.0, Phase::kVehicleRun);
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_SENSOR_MODEL_H_
