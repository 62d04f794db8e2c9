#ifndef ACCELCAL_MODELS_TRIAD_H_
#define ACCELCAL_MODELS_TRIAD_H_

// The three-axis accelerometer (triad) in imu_tk's convention (docs/triad.md):
//
//   a = T K (u - b),   T = [ 1  -yz   zy ]    K = diag(gain_x, gain_y, gain_z)
//                          [ 0   1   -zx ]
//                          [ 0   0    1  ]
//
// u: the raw output (counts), b: offset (counts), K: gain ((m/s^2)/count), T: the small
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
template <typename T>
void TriadSpecificForce(const T* parameters, const double* raw, T* specific_force) {
  const T ux = parameters[kTriadGainX] * (T(raw[0]) - parameters[kTriadOffsetX]);
  const T uy = parameters[kTriadGainY] * (T(raw[1]) - parameters[kTriadOffsetY]);
  const T uz = parameters[kTriadGainZ] * (T(raw[2]) - parameters[kTriadOffsetZ]);
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
  raw[0] = vx / parameters[kTriadGainX] + parameters[kTriadOffsetX];
  raw[1] = vy / parameters[kTriadGainY] + parameters[kTriadOffsetY];
  raw[2] = vz / parameters[kTriadGainZ] + parameters[kTriadOffsetZ];
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_H_
