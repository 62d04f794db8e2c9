#ifndef ACCELCAL_MODELS_TRIAD_H_
#define ACCELCAL_MODELS_TRIAD_H_

// The three-axis accelerometer (triad) in imu_tk's convention (docs/triad.md):
//
//   a = T K (u - b),   T = [ 1  -yz   zy ]    K = diag(gain_x, gain_y, gain_z)
//                          [ 0   1   -zx ]
//                          [ 0   0    1  ]
//
// u: the raw output (counts), b: offset (counts), K: gain ((m/s^2)/count), T: the small
// non-orthogonality angles (rad). Axis k reads the force along row k of T^-1, upper-triangular
// too, so the orthogonal frame of a has its z along the z sensing axis and its y in the plane of
// the y and z sensing axes (docs/triad.md). a: specific force in m/s^2, in that frame.
//
// The parameters form one block of kTriadParameterCount doubles at the offsets below (the
// order imu_tk's solver uses, so that the same problem is solved step by step).
//
// Optionally (TriadMlOptions::scale_nonlinearity), a second-order scale term per axis, the
// triad's counterpart of the tilt table's k2_k (../shared/spec/error-model.md,
// models/effects/scale_nonlinearity.h: m_k += k2_k f_k^2), with the same name, unit and
// sign. It acts where the tilt table's does, in the sensor's direction: with w = T^-1 a the
// specific force along the sensing axes (m/s^2) and v_k = gain_k (u_k - offset_k) the
// gain-corrected output of axis k (m/s^2),
//
//   v_k = w_k + k2_k w_k^2,   k2_k = scale_nonlinearity_k [1/(m/s^2)],
//
// so a positive k2_k makes the axis read more than linear at large |w_k| of either sign.
// It is its own block of kTriadScaleNonlinearityCount doubles, so that the 9-parameter
// problem is unchanged when the term is not estimated.

#include <array>
#include <cmath>
#include <string>

namespace accelcal {

constexpr int kTriadMisalignmentYz = 0;  // rad: y sensing axis tilted towards x
constexpr int kTriadMisalignmentZy = 1;  // rad: z sensing axis tilted towards x
constexpr int kTriadMisalignmentZx = 2;  // rad: z sensing axis tilted towards y
constexpr int kTriadGainX = 3;           // (m/s^2)/count
constexpr int kTriadGainY = 4;
constexpr int kTriadGainZ = 5;
constexpr int kTriadOffsetX = 6;  // counts
constexpr int kTriadOffsetY = 7;
constexpr int kTriadOffsetZ = 8;
constexpr int kTriadParameterCount = 9;

// The names and units the outputs use, in block order.
struct TriadParameterInfo {
  const char* name;
  const char* unit;
};
inline const std::array<TriadParameterInfo, kTriadParameterCount>& TriadParameterInfos() {
  static const std::array<TriadParameterInfo, kTriadParameterCount> infos = {{
      {"misalignment_yz", "rad"},
      {"misalignment_zy", "rad"},
      {"misalignment_zx", "rad"},
      {"gain_x", "(m/s^2)/count"},
      {"gain_y", "(m/s^2)/count"},
      {"gain_z", "(m/s^2)/count"},
      {"offset_x", "count"},
      {"offset_y", "count"},
      {"offset_z", "count"},
  }};
  return infos;
}

using TriadParameters = std::array<double, kTriadParameterCount>;

constexpr int kTriadScaleNonlinearityCount = 3;  // x, y, z, in 1/(m/s^2)
inline const std::array<TriadParameterInfo, kTriadScaleNonlinearityCount>&
TriadScaleNonlinearityInfos() {
  static const std::array<TriadParameterInfo, kTriadScaleNonlinearityCount> infos = {{
      {"scale_nonlinearity_x", "1/(m/s^2)"},
      {"scale_nonlinearity_y", "1/(m/s^2)"},
      {"scale_nonlinearity_z", "1/(m/s^2)"},
  }};
  return infos;
}

using TriadScaleNonlinearity = std::array<double, kTriadScaleNonlinearityCount>;

// The identity calibration of imu_tk (angles 0, gains 1) with the given offsets.
inline TriadParameters TriadParametersWithOffset(double offset_x, double offset_y,
                                                 double offset_z) {
  TriadParameters p{};
  p[kTriadGainX] = p[kTriadGainY] = p[kTriadGainZ] = 1.0;
  p[kTriadOffsetX] = offset_x;
  p[kTriadOffsetY] = offset_y;
  p[kTriadOffsetZ] = offset_z;
  return p;
}

// a = T K (u - b). T is a scalar or a ceres::Jet; `raw` is the measured output in counts.
// With `scale_nonlinearity` (k2, may be null: no second-order term) each gain-corrected output
// v_k is first mapped back to the force along its axis, w_k = 2 v_k / (1 + sqrt(1 + 4 k2_k v_k))
// (the root of k2 w^2 + w - v = 0 that tends to v as k2 -> 0, written without cancellation),
// and a = T w. Returns false when 1 + 4 k2_k v_k < 0: no force gives that output.
template <typename T>
bool TriadSpecificForce(const T* parameters, const T* scale_nonlinearity, const double* raw,
                        T* specific_force) {
  using std::sqrt;  // ceres::Jet's sqrt is found by argument-dependent lookup
  T along[3];
  for (int k = 0; k < 3; ++k) {
    const T v = parameters[kTriadGainX + k] * (T(raw[k]) - parameters[kTriadOffsetX + k]);
    if (scale_nonlinearity == nullptr) {
      along[k] = v;
      continue;
    }
    const T discriminant = T(1.0) + T(4.0) * scale_nonlinearity[k] * v;
    if (!(discriminant >= T(0.0))) return false;
    along[k] = T(2.0) * v / (T(1.0) + sqrt(discriminant));
  }
  specific_force[0] = along[0] - parameters[kTriadMisalignmentYz] * along[1] +
                      parameters[kTriadMisalignmentZy] * along[2];
  specific_force[1] = along[1] - parameters[kTriadMisalignmentZx] * along[2];
  specific_force[2] = along[2];
  return true;
}

// The 9-parameter model (no second-order term).
template <typename T>
void TriadSpecificForce(const T* parameters, const double* raw, T* specific_force) {
  TriadSpecificForce(parameters, static_cast<const T*>(nullptr), raw, specific_force);
}

// The inverse, u = K^-1 (w + k2 w^2) + b with w = T^-1 a: what the triad outputs under the
// specific force `a` (the simulator's direction and the maximum-likelihood residual's).
// T is unit upper-triangular, so T^-1 a is back-substitution. `scale_nonlinearity` may be
// null (no second-order term).
template <typename T>
void TriadRawOutput(const T* parameters, const T* scale_nonlinearity, const T* specific_force,
                    T* raw) {
  T along[3];
  along[2] = specific_force[2];
  along[1] = specific_force[1] + parameters[kTriadMisalignmentZx] * along[2];
  along[0] = specific_force[0] + parameters[kTriadMisalignmentYz] * along[1] -
             parameters[kTriadMisalignmentZy] * along[2];
  for (int k = 0; k < 3; ++k) {
    T v = along[k];
    if (scale_nonlinearity != nullptr) v += scale_nonlinearity[k] * along[k] * along[k];
    raw[k] = v / parameters[kTriadGainX + k] + parameters[kTriadOffsetX + k];
  }
}

// The 9-parameter model (no second-order term).
template <typename T>
void TriadRawOutput(const T* parameters, const T* specific_force, T* raw) {
  TriadRawOutput(parameters, static_cast<const T*>(nullptr), specific_force, raw);
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_H_
