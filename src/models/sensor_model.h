#ifndef ACCELCAL_MODELS_SENSOR_MODEL_H_
#define ACCELCAL_MODELS_SENSOR_MODEL_H_

// The accelerometer pair's forward model, exactly as ../shared/spec/error-model.md
// ("Sensor output") defines it. Everything that predicts a sensor output (Ceres
// residuals, the closed-form baseline, the simulator) calls these functions, so they
// cannot disagree.
//
// The y sensing axis may be tilted toward x by the non-orthogonality eps [rad]:
//
//   f_along_x = fx
//   f_along_y = fy cos(eps) + fx sin(eps)
//
// and each axis k in {x, y} outputs [m/s^2]
//
//   m_k = (1 + s_k) f_along_k + k2_k f_along_k^2 + b_k + d_k u_i + r_k + zeta_k
//
// with d_k u_i present only in the calibration test and r_k only in the vehicle run.
// The noise zeta_k is not part of the deterministic prediction; the simulator adds it.
// The baseline model of the reference report is b_k, s_k only (every other term zero).

#include <cmath>

namespace accelcal {

// Which part of the experiment a sample belongs to. The drift d_k exists only in the
// calibration test; the bias shift r_k only in the vehicle run.
enum class Phase { kCalibrationTest, kVehicleRun };

// One axis's error terms, named as in the spec's outputs (bias_x, scale_x, ...).
template <typename T>
struct AxisErrors {
  T bias = T(0.0);                // b_k, m/s^2
  T scale = T(0.0);               // s_k, dimensionless
  T scale_nonlinearity = T(0.0);  // k2_k, 1/(m/s^2)
  T bias_drift = T(0.0);          // d_k, m/s^2 from first to last calibration sample
  T run_bias_shift = T(0.0);      // r_k, m/s^2 (run bias minus test bias)
};

// u_i = i/(N-1) - 0.5 for sample i of N calibration samples, so that the drift term
// has zero mean and b_k stays the mean bias over the test. A single sample has u = 0.
inline double DriftCoordinate(int sample_index, int sample_count) {
  if (sample_count < 2) return 0.0;
  return static_cast<double>(sample_index) / static_cast<double>(sample_count - 1) - 0.5;
}

// Projects the true specific force (reference frame) on the two sensing axes.
template <typename T>
void ProjectOnSensingAxes(const T& specific_force_x, const T& specific_force_y,
                          const T& nonorthogonality_rad, T* along_x, T* along_y) {
  using std::cos;
  using std::sin;
  *along_x = specific_force_x;
  *along_y =
      specific_force_y * cos(nonorthogonality_rad) + specific_force_x * sin(nonorthogonality_rad);
}

// The noiseless output of one axis for the specific force along it.
// `drift_coordinate` is u_i (see DriftCoordinate) and is ignored in the vehicle run.
template <typename T>
T AxisOutput(const T& specific_force_along_axis, const AxisErrors<T>& errors,
             double drift_coordinate, Phase phase) {
  const T& f = specific_force_along_axis;
  T output = (T(1.0) + errors.scale) * f + errors.scale_nonlinearity * f * f + errors.bias;
  if (phase == Phase::kCalibrationTest) {
    output += errors.bias_drift * T(drift_coordinate);
  } else {
    output += errors.run_bias_shift;
  }
  return output;
}

// The inverse of AxisOutput in the vehicle run: the specific force along the axis that
// produces the noiseless output `measured`. With c = b + r - m the model is
// k2 f^2 + (1 + s) f + c = 0; the root that tends to the linear inverse (m - b - r)/(1 + s)
// as k2 -> 0 is written without cancellation as f = -2c / ((1 + s) + sqrt((1 + s)^2 - 4 k2 c)).
// A negative discriminant (an output no force can produce) is clamped at zero.
template <typename T>
T InvertAxisOutput(const T& measured, const AxisErrors<T>& errors) {
  using std::sqrt;
  const T one_plus_scale = T(1.0) + errors.scale;
  const T c = errors.bias + errors.run_bias_shift - measured;
  T discriminant = one_plus_scale * one_plus_scale - T(4.0) * errors.scale_nonlinearity * c;
  if (discriminant < T(0.0)) discriminant = T(0.0);
  return T(-2.0) * c / (one_plus_scale + sqrt(discriminant));
}

// Both axes of a sensor: the errors of each axis and the y axis' tilt toward x.
template <typename T>
struct SensorErrors {
  AxisErrors<T> x;
  AxisErrors<T> y;
  T nonorthogonality = T(0.0);  // eps, rad
};

// Undoes ProjectOnSensingAxes: the reference-frame force from the forces along the
// sensing axes, fx = f_along_x, fy = (f_along_y - fx sin(eps)) / cos(eps). Linear in the
// forces, so it may be applied to weighted sums of them as well as to one sample.
template <typename T>
void UndoProjection(const T& along_x, const T& along_y, const T& nonorthogonality_rad,
                    T* specific_force_x, T* specific_force_y) {
  using std::cos;
  using std::sin;
  *specific_force_x = along_x;
  *specific_force_y = (along_y - along_x * sin(nonorthogonality_rad)) / cos(nonorthogonality_rad);
}

// The vehicle's acceleration (reference frame) recovered from one run sample: each axis
// inverted (InvertAxisOutput), then the projection undone (UndoProjection).
template <typename T>
void CorrectRunSample(const T& measured_x, const T& measured_y, const SensorErrors<T>& errors,
                      T* acceleration_x, T* acceleration_y) {
  UndoProjection(InvertAxisOutput(measured_x, errors.x), InvertAxisOutput(measured_y, errors.y),
                 errors.nonorthogonality, acceleration_x, acceleration_y);
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_SENSOR_MODEL_H_
