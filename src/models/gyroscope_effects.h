#ifndef ACCELCAL_MODELS_GYROSCOPE_EFFECTS_H_
#define ACCELCAL_MODELS_GYROSCOPE_EFFECTS_H_

// The gyroscope's effects beyond models/gyroscope.h's 9 parameters and offset (docs/gyroscope.md),
// in one place: what the maximum-likelihood calibration can estimate, discovery can test, and the
// simulator can put in a log. Every coefficient is 0 for the model of models/gyroscope.h.
//
// The calibrated rate, in the correction's direction (from the output u to the rate w):
//
//   v_k  = gain_k (u_k - b_k)                                  (rad/s along sensing axis k)
//   v'_k = v_k + asymmetry_k |v_k| + nonlinearity_k v_k^2      (per axis)
//   w    = T v' - G f                                          (rad/s)
//
//   G (9 coefficients, row-major, (rad/s)/(m/s^2)): the g-sensitivity, imucal's K_ga; f the
//     specific force the calibrated accelerometer measures (m/s^2, the accelerometer's frame);
//   asymmetry_k (dimensionless): axis k's gain is gain_k (1 + asymmetry_k) for positive rates
//     and gain_k (1 - asymmetry_k) for negative ones;
//   nonlinearity_k (1/(rad/s)): the second-order scale term of axis k.
//
// The effects, each a group of coefficients that discovery tests as one candidate:
//   g_sensitivity (9), scale_asymmetry (3), scale_nonlinearity (3).

#include <array>
#include <cmath>
#include <string>

#include "models/gyroscope.h"

namespace accelcal {

constexpr int kGyroscopeGSensitivity = 0;        // G(0,0) .. G(2,2), row-major
constexpr int kGyroscopeScaleAsymmetry = 9;      // x, y, z
constexpr int kGyroscopeScaleNonlinearity = 12;  // x, y, z
constexpr int kGyroscopeEffectCoefficientCount = 15;

using GyroscopeEffectCoefficients = std::array<double, kGyroscopeEffectCoefficientCount>;

struct GyroscopeEffectInfo {
  const char* name;        // the group's name in outputs
  int first;               // its first coefficient
  int coefficients;        // how many
  const char* unit;        // its coefficients' unit
  const char* meaning;     // in a user's words
  const char* suggestion;  // what a user can do when it is found
};

constexpr int kGyroscopeEffectCount = 3;
inline const std::array<GyroscopeEffectInfo, kGyroscopeEffectCount>& GyroscopeEffectInfos() {
  static const std::array<GyroscopeEffectInfo, kGyroscopeEffectCount> infos = {{
      {"g_sensitivity", kGyroscopeGSensitivity, 9, "(rad/s)/(m/s^2)",
       "the gyroscope reads a rate proportional to the specific force (imucal's K_ga)",
       "calibrate it with the rest (its 9 terms are in the calibration) or mount the sensor so "
       "that vibration and tilt do not reach it"},
      {"scale_asymmetry", kGyroscopeScaleAsymmetry, 3, "1",
       "an axis's gain differs between positive and negative rates",
       "turn the sensor both ways about every axis; the gains of a one-way session hide it"},
      {"scale_nonlinearity", kGyroscopeScaleNonlinearity, 3, "1/(rad/s)",
       "an axis's gain changes with the rate (a second-order scale term)",
       "keep turns within the rate range the sensor will see in use, or calibrate the term"},
  }};
  return infos;
}

// The name of coefficient c: g_sensitivity_xy (row x, column y), scale_asymmetry_x, ...
inline std::string GyroscopeEffectCoefficientName(int c) {
  static const char kAxes[] = "xyz";
  if (c < kGyroscopeScaleAsymmetry) {
    return std::string("gyroscope_g_sensitivity_") + kAxes[c / 3] + kAxes[c % 3];
  }
  if (c < kGyroscopeScaleNonlinearity)
    return std::string("gyroscope_scale_asymmetry_") + kAxes[c - kGyroscopeScaleAsymmetry];
  return std::string("gyroscope_scale_nonlinearity_") + kAxes[c - kGyroscopeScaleNonlinearity];
}

inline const char* GyroscopeEffectCoefficientUnit(int c) {
  for (const GyroscopeEffectInfo& info : GyroscopeEffectInfos())
    if (c >= info.first && c < info.first + info.coefficients) return info.unit;
  return "";
}

// w from the output u (counts or the log's unit) and the specific force f (m/s^2). `effects`
// may be null (all coefficients 0).
template <typename T>
void GyroscopeCorrectedRate(const T* parameters, const T* offset, const T* effects,
                            const double* raw, const double* specific_force, T* rate) {
  using std::abs;
  T along[3];
  for (int k = 0; k < 3; ++k) {
    along[k] = parameters[kGyroscopeGainX + k] * (T(raw[k]) - offset[k]);
    if (effects != nullptr) {
      along[k] += effects[kGyroscopeScaleAsymmetry + k] * abs(along[k]) +
                  effects[kGyroscopeScaleNonlinearity + k] * along[k] * along[k];
    }
  }
  T m[9];
  GyroscopeMisalignmentMatrix(parameters, m);
  for (int row = 0; row < 3; ++row) {
    rate[row] = m[3 * row] * along[0] + m[3 * row + 1] * along[1] + m[3 * row + 2] * along[2];
    if (effects != nullptr) {
      for (int k = 0; k < 3; ++k)
        rate[row] -= effects[kGyroscopeGSensitivity + 3 * row + k] * T(specific_force[k]);
    }
  }
}

// The inverse: the output u at the rate w (rad/s) and specific force f (m/s^2), what a gyroscope
// with these effects reads (the simulator's direction, and the rest's prediction). The per-axis
// terms are inverted by Newton's method from v' (a few steps: they are small).
template <typename T>
void GyroscopeRawWithEffects(const T* parameters, const T* offset, const T* effects, const T* rate,
                             const T* specific_force, T* raw) {
  using std::abs;
  T sensed[3];
  for (int row = 0; row < 3; ++row) {
    sensed[row] = rate[row];
    if (effects != nullptr) {
      for (int k = 0; k < 3; ++k)
        sensed[row] += effects[kGyroscopeGSensitivity + 3 * row + k] * specific_force[k];
    }
  }
  // v' = T^-1 (w + G f): GyroscopeRawOutput with gains 1 and offset 0 gives T^-1 x.
  T unit_gains[kGyroscopeParameterCount];
  for (int i = 0; i < kGyroscopeParameterCount; ++i) unit_gains[i] = parameters[i];
  for (int k = 0; k < 3; ++k) unit_gains[kGyroscopeGainX + k] = T(1.0);
  const T zero[3] = {T(0.0), T(0.0), T(0.0)};
  T primed[3];
  GyroscopeRawOutput(unit_gains, zero, sensed, primed);
  for (int k = 0; k < 3; ++k) {
    T along = primed[k];
    if (effects != nullptr) {
      const T a = effects[kGyroscopeScaleAsymmetry + k];
      const T n = effects[kGyroscopeScaleNonlinearity + k];
      for (int step = 0; step < 6; ++step) {
        const T sign = along < T(0.0) ? T(-1.0) : T(1.0);
        const T value = along + a * abs(along) + n * along * along - primed[k];
        const T slope = T(1.0) + a * sign + T(2.0) * n * along;
        along -= value / slope;
      }
    }
    raw[k] = along / parameters[kGyroscopeGainX + k] + offset[k];
  }
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_EFFECTS_H_
