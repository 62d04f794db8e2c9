#ifndef ACCELCAL_MODELS_TRIAD_H_
#define ACCELCAL_MODELS_TRIAD_H_

// The three-axis accelerometer (triad) in imu_tk's convention (docs/triad.md):
//
//   a = T K (u - b),   T = [ 1  -yz   zy ]    K = diag(scale_x, scale_y, scale_z)
//                          [ 0   1   -zx ]
//                          [ 0   0    1  ]
//
// u: the raw output (counts), b: bias (counts), K: gain ((m/s^2)/count), T: the small
// non-orthogonality angles (rad) that map the sensing axes onto an orthogonal frame whose
// x is the x sensing axis and whose y lies in the plane of the x and y sensing axes (so the
// lower triangle is zero). a: specific force in m/s^2, in that frame.
//
// The parameters form one block of kTriadParameterCount doubles at the offsets below (the
// order imu_tk's solver uses, so that the same problem is solved step by step).

#include <array>
#include <string>

namespace accelcal {

constexpr int kTriadMisalignmentYz = 0;  // rad: y sensing axis tilted towards x
constexpr int kTriadMisalignmentZy = 1;  // rad: z sensing axis tilted towards x
constexpr int kTriadMisalignmentZx = 2;  // rad: z sensing axis tilted towards y
constexpr int kTriadScaleX = 3;          // (m/s^2)/count
constexpr int kTriadScaleY = 4;
constexpr int kTriadScaleZ = 5;
constexpr int kTriadBiasX = 6;  // counts
constexpr int kTriadBiasY = 7;
constexpr int kTriadBiasZ = 8;
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
      {"scale_x", "(m/s^2)/count"},
      {"scale_y", "(m/s^2)/count"},
      {"scale_z", "(m/s^2)/count"},
      {"bias_x", "count"},
      {"bias_y", "count"},
      {"bias_z", "count"},
  }};
  return infos;
}

using TriadParameters = std::array<double, kTriadParameterCount>;

// The identity calibration of imu_tk (angles 0, gains 1) with the given bias.
inline TriadParameters TriadParametersWithBias(double bias_x, double bias_y, double bias_z) {
  TriadParameters p{};
  p[kTriadScaleX] = p[kTriadScaleY] = p[kTriadScaleZ] = 1.0;
  p[kTriadBiasX] = bias_x;
  p[kTriadBiasY] = bias_y;
  p[kTriadBiasZ] = bias_z;
  return p;
}

// a = T K (u - b). T is a scalar or a ceres::Jet; `raw` is the measured output in counts.
template <typename T>
void TriadSpecificForce(const T* parameters, const double* raw, T* specific_force) {
  const T ux = parameters[kTriadScaleX] * (T(raw[0]) - parameters[kTriadBiasX]);
  const T uy = parameters[kTriadScaleY] * (T(raw[1]) - parameters[kTriadBiasY]);
  const T uz = parameters[kTriadScaleZ] * (T(raw[2]) - parameters[kTriadBiasZ]);
  specific_force[0] =
      ux - parameters[kTriadMisalignmentYz] * uy + parameters[kTriadMisalignmentZy] * uz;
  specific_force[1] = uy - parameters[kTriadMisalignmentZx] * uz;
  specific_force[2] = uz;
}

// The inverse, u = K^-1 T^-1 a + b: what the triad outputs under the specific force `a`
// (the simulator's direction). T is unit upper-triangular, so T^-1 a is back-substitution.
template <typename T>
void TriadRawOutput(const T* parameters, const T* specific_force, T* raw) {
  const T vz = specific_force[2];
  const T vy = specific_force[1] + parameters[kTriadMisalignmentZx] * vz;
  const T vx = specific_force[0] + parameters[kTriadMisalignmentYz] * vy -
               parameters[kTriadMisalignmentZy] * vz;
  raw[0] = vx / parameters[kTriadScaleX] + parameters[kTriadBiasX];
  raw[1] = vy / parameters[kTriadScaleY] + parameters[kTriadBiasY];
  raw[2] = vz / parameters[kTriadScaleZ] + parameters[kTriadBiasZ];
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_H_
