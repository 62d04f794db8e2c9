#ifndef ACCELCAL_MODELS_GYROSCOPE_H_
#define ACCELCAL_MODELS_GYROSCOPE_H_

// The three-axis gyroscope in imu_tk's convention (docs/gyroscope.md; Tedaldi, Pretto,
// Menegatti, ICRA 2014, eq. 2 and 6; imu_tk's CalibratedTriad with all six angles):
//
//   w = T K (u - b),   T = [  1   -yz   zy ]    K = diag(gain_x, gain_y, gain_z)
//                          [  xz   1   -zx ]
//                          [ -xy   yx   1  ]
//
// u: the raw output (counts), b: offset (counts), K: gain ((rad/s)/count), w: the angular rate
// (rad/s) in the accelerometer's orthogonal frame (models/triad.h, docs/triad.md: z along the
// accelerometer's z sensing axis). The gravity directions that calibrate the gyroscope come from
// the calibrated accelerometer, so the gyroscope's axes are placed relative to that frame and
// all six small angles (rad) are observable, where the accelerometer has three. Angle ij is
// imu_tk's mis_ij: the i sensing axis rotated about the j axis.
//
// The 9 parameters imu_tk estimates form one block of kGyroscopeParameterCount doubles at the
// offsets below (imu_tk's order); the offset is its own block of 3 (imu_tk takes it from the
// initial rest and does not estimate it).
//
// Also here, because the gyroscope's calibration is defined through it: imu_tk's integration of
// the angular rate into a rotation (its integration.h), a fourth-order Runge-Kutta step of the
// quaternion kinematics per pair of samples, and the rotation matrix of the result.

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace accelcal {

constexpr int kGyroscopeMisalignmentYz = 0;  // rad: T(0,1) = -yz
constexpr int kGyroscopeMisalignmentZy = 1;  // rad: T(0,2) = +zy
constexpr int kGyroscopeMisalignmentZx = 2;  // rad: T(1,2) = -zx
constexpr int kGyroscopeMisalignmentXz = 3;  // rad: T(1,0) = +xz
constexpr int kGyroscopeMisalignmentXy = 4;  // rad: T(2,0) = -xy
constexpr int kGyroscopeMisalignmentYx = 5;  // rad: T(2,1) = +yx
constexpr int kGyroscopeGainX = 6;           // (rad/s)/count
constexpr int kGyroscopeGainY = 7;
constexpr int kGyroscopeGainZ = 8;
constexpr int kGyroscopeParameterCount = 9;

// The names and units the outputs use, in block order.
struct GyroscopeParameterInfo {
  const char* name;
  const char* unit;
};
inline const std::array<GyroscopeParameterInfo, kGyroscopeParameterCount>&
GyroscopeParameterInfos() {
  static const std::array<GyroscopeParameterInfo, kGyroscopeParameterCount> infos = {{
      {"gyroscope_misalignment_yz", "rad"},
      {"gyroscope_misalignment_zy", "rad"},
      {"gyroscope_misalignment_zx", "rad"},
      {"gyroscope_misalignment_xz", "rad"},
      {"gyroscope_misalignment_xy", "rad"},
      {"gyroscope_misalignment_yx", "rad"},
      {"gyroscope_gain_x", "(rad/s)/count"},
      {"gyroscope_gain_y", "(rad/s)/count"},
      {"gyroscope_gain_z", "(rad/s)/count"},
  }};
  return infos;
}

using GyroscopeParameters = std::array<double, kGyroscopeParameterCount>;
using GyroscopeOffset = std::array<double, 3>;  // counts, x, y, z

// A gyroscope's whole calibration, block and offset: the block's 9 in its order, then the
// offset's x, y, z. The order of a calibration file's gyroscope section and of its 12x12
// covariance (io/calibration_file.h).
constexpr int kGyroscopeCalibrationOffsetX = kGyroscopeParameterCount;
constexpr int kGyroscopeCalibrationParameterCount = kGyroscopeParameterCount + 3;

// The name of parameter `index` of the 12: the block's (GyroscopeParameterInfos), then
// "gyroscope_offset_x", "gyroscope_offset_y", "gyroscope_offset_z".
inline std::string GyroscopeCalibrationParameterName(int index) {
  if (index < kGyroscopeParameterCount) return GyroscopeParameterInfos()[index].name;
  return std::string("gyroscope_offset_") + "xyz"[index - kGyroscopeCalibrationOffsetX];
}

// Angles 0 and the given gains (imu_tk's default guess has gains 1; its Xsens example 1/6258).
inline GyroscopeParameters GyroscopeParametersWithGain(double gain_x, double gain_y,
                                                       double gain_z) {
  GyroscopeParameters p{};
  p[kGyroscopeGainX] = gain_x;
  p[kGyroscopeGainY] = gain_y;
  p[kGyroscopeGainZ] = gain_z;
  return p;
}

// T, row-major, as imu_tk prints it ("Misalignment Matrix").
template <typename T>
void GyroscopeMisalignmentMatrix(const T* parameters, T matrix[9]) {
  matrix[0] = T(1.0);
  matrix[1] = -parameters[kGyroscopeMisalignmentYz];
  matrix[2] = parameters[kGyroscopeMisalignmentZy];
  matrix[3] = parameters[kGyroscopeMisalignmentXz];
  matrix[4] = T(1.0);
  matrix[5] = -parameters[kGyroscopeMisalignmentZx];
  matrix[6] = -parameters[kGyroscopeMisalignmentXy];
  matrix[7] = parameters[kGyroscopeMisalignmentYx];
  matrix[8] = T(1.0);
}

// w = T K (u - b). `parameters` (the 9-block) and `offset` (counts) are scalars or ceres::Jets;
// `raw` is the measured output in counts; `angular_rate` in rad/s.
template <typename T>
void GyroscopeAngularRate(const T* parameters, const T* offset, const double* raw,
                          T* angular_rate) {
  T along[3];
  for (int k = 0; k < 3; ++k) along[k] = parameters[kGyroscopeGainX + k] * (T(raw[k]) - offset[k]);
  T matrix[9];
  GyroscopeMisalignmentMatrix(parameters, matrix);
  for (int row = 0; row < 3; ++row) {
    angular_rate[row] = matrix[3 * row] * along[0] + matrix[3 * row + 1] * along[1] +
                        matrix[3 * row + 2] * along[2];
  }
}

// The inverse, u = K^-1 T^-1 w + b: what the gyroscope outputs at the angular rate `w` (rad/s;
// the simulator's direction). T^-1 by its adjugate; T is near the identity for small angles.
template <typename T>
void GyroscopeRawOutput(const T* parameters, const T* offset, const T* angular_rate, T* raw) {
  T m[9];
  GyroscopeMisalignmentMatrix(parameters, m);
  const T adjugate[9] = {
      m[4] * m[8] - m[5] * m[7], m[2] * m[7] - m[1] * m[8], m[1] * m[5] - m[2] * m[4],
      m[5] * m[6] - m[3] * m[8], m[0] * m[8] - m[2] * m[6], m[2] * m[3] - m[0] * m[5],
      m[3] * m[7] - m[4] * m[6], m[1] * m[6] - m[0] * m[7], m[0] * m[4] - m[1] * m[3]};
  const T determinant = m[0] * adjugate[0] + m[1] * adjugate[3] + m[2] * adjugate[6];
  for (int k = 0; k < 3; ++k) {
    const T along = (adjugate[3 * k] * angular_rate[0] + adjugate[3 * k + 1] * angular_rate[1] +
                     adjugate[3 * k + 2] * angular_rate[2]) /
                    determinant;
    raw[k] = along / parameters[kGyroscopeGainX + k] + offset[k];
  }
}

// ---------------------------------------------------------------------------------------------
// Integration (imu_tk's integration.h, reimplemented): the attitude quaternion q = (w, x, y, z)
// of the body in the frame it started in obeys dq/dt = 1/2 q (x) (0, w_body), that is
// dq/dt = 1/2 Omega(w) q with
//
//   Omega(w) = [ 0   -wx  -wy  -wz ]
//              [ wx   0    wz  -wy ]
//              [ wy  -wz   0    wx ]
//              [ wz   wy  -wx   0  ]
//
// One step from sample i to i + 1 (rates w0, w1, time step dt) is classic RK4 with the rate at the
// middle taken as the mean (w0 + w1) / 2 for the second and third stages:
//   k1 = f(q, w0), k2 = f(q + dt/2 k1, w01), k3 = f(q + dt/2 k2, w01), k4 = f(q + dt k3, w1),
//   q' = q + dt (k1 + 2 k2 + 2 k3 + k4) / 6, then q' / |q'|.

namespace gyroscope_internal {
template <typename T>
void QuaternionRate(const T* q, const T* w, T* q_dot) {
  q_dot[0] = T(0.5) * (-w[0] * q[1] - w[1] * q[2] - w[2] * q[3]);
  q_dot[1] = T(0.5) * (w[0] * q[0] + w[2] * q[2] - w[1] * q[3]);
  q_dot[2] = T(0.5) * (w[1] * q[0] - w[2] * q[1] + w[0] * q[3]);
  q_dot[3] = T(0.5) * (w[2] * q[0] + w[1] * q[1] - w[0] * q[2]);
}
}  // namespace gyroscope_internal

// One RK4 step, `quaternion` updated in place, with the rate at the step's middle given; rates in
// rad/s, `step_s` in s.
template <typename T>
void QuaternionRk4Step(const T* rate_before, const T* rate_middle, const T* rate_after,
                       double step_s, T* quaternion) {
  using std::sqrt;  // ceres::Jet's sqrt is found by argument-dependent lookup
  const T dt(step_s);
  T k1[4], k2[4], k3[4], k4[4], stage[4];
  gyroscope_internal::QuaternionRate(quaternion, rate_before, k1);
  for (int j = 0; j < 4; ++j) stage[j] = quaternion[j] + T(0.5) * dt * k1[j];
  gyroscope_internal::QuaternionRate(stage, rate_middle, k2);
  for (int j = 0; j < 4; ++j) stage[j] = quaternion[j] + T(0.5) * dt * k2[j];
  gyroscope_internal::QuaternionRate(stage, rate_middle, k3);
  for (int j = 0; j < 4; ++j) stage[j] = quaternion[j] + dt * k3[j];
  gyroscope_internal::QuaternionRate(stage, rate_after, k4);
  const T sixth(1.0 / 6.0);
  const T third(1.0 / 3.0);
  T norm_squared(0.0);
  for (int j = 0; j < 4; ++j) {
    quaternion[j] += dt * (sixth * k1[j] + third * k2[j] + third * k3[j] + sixth * k4[j]);
    norm_squared += quaternion[j] * quaternion[j];
  }
  const T norm = sqrt(norm_squared);
  for (int j = 0; j < 4; ++j) quaternion[j] /= norm;
}

// imu_tk's step: the middle rate is the mean of the two samples'.
template <typename T>
void QuaternionRk4Step(const T* rate_before, const T* rate_after, double step_s, T* quaternion) {
  const T rate_middle[3] = {T(0.5) * (rate_before[0] + rate_after[0]),
                            T(0.5) * (rate_before[1] + rate_after[1]),
                            T(0.5) * (rate_before[2] + rate_after[2])};
  QuaternionRk4Step(rate_before, rate_middle, rate_after, step_s, quaternion);
}

// The rotation matrix (row-major) of a quaternion (w, x, y, z), scaled by 1/|q|^2 as Ceres'
// QuaternionToRotation does: R maps the body's vectors to the frame it started in.
template <typename T>
void QuaternionToRotationMatrix(const T* q, T* rotation) {
  const T aa = q[0] * q[0], ab = q[0] * q[1], ac = q[0] * q[2], ad = q[0] * q[3];
  const T bb = q[1] * q[1], bc = q[1] * q[2], bd = q[1] * q[3];
  const T cc = q[2] * q[2], cd = q[2] * q[3], dd = q[3] * q[3];
  const T scale = T(1.0) / (aa + bb + cc + dd);
  rotation[0] = scale * (aa + bb - cc - dd);
  rotation[1] = scale * T(2.0) * (bc - ad);
  rotation[2] = scale * T(2.0) * (ac + bd);
  rotation[3] = scale * T(2.0) * (ad + bc);
  rotation[4] = scale * (aa - bb + cc - dd);
  rotation[5] = scale * T(2.0) * (cd - ab);
  rotation[6] = scale * T(2.0) * (bd - ac);
  rotation[7] = scale * T(2.0) * (ab + cd);
  rotation[8] = scale * (aa - bb - cc + dd);
}

// imu_tk's integrateGyroInterval over `sample_count` rates: from the identity, one RK4 step per
// pair of consecutive rates, step j (from rate j to rate j + 1) of step_s[j] seconds, so
// sample_count - 1 steps; the rotation matrix of the result, row-major (the body's final
// attitude in its first frame). rate_at(j, T* rate) writes rate j (rad/s), each j once, in order.
template <typename T, typename RateAt>
void IntegrateAngularRate(int sample_count, const RateAt& rate_at,
                          const std::vector<double>& step_s, T* rotation) {
  T quaternion[4] = {T(1.0), T(0.0), T(0.0), T(0.0)};
  T rate_before[3];
  T rate_after[3];
  if (sample_count > 0) rate_at(0, rate_before);
  for (int j = 0; j + 1 < sample_count; ++j) {
    rate_at(j + 1, rate_after);
    QuaternionRk4Step(rate_before, rate_after, step_s[j], quaternion);
    for (int k = 0; k < 3; ++k) rate_before[k] = rate_after[k];
  }
  QuaternionToRotationMatrix(quaternion, rotation);
}

// The fourth-order rule of the maximum-likelihood calibration (docs/gyroscope.md): the same RK4
// steps, the middle rate from the cubic Hermite interpolant of the rates, whose slopes are central
// differences of the samples (one-sided at the ends):
//   w(t_j + dt/2) = (w_j + w_j+1) / 2 + dt (w'_j - w'_j+1) / 8.
// About a fixed axis it adds dt (w_j + w_j+1) / 2 + dt^2 (w'_j - w'_j+1) / 12 per step, the
// trapezoid rule with its end correction: exact for a cubic rate, where imu_tk's rule leaves the
// error dt^2 (w'(end) - w'(start)) / 12 of the trapezoid. rate_at(j, T* rate) writes rate j
// (any order; called more than once per j).
// `path`, when not null, gets the attitude quaternion at every sample (the identity at the first).
template <typename T, typename RateAt>
void IntegrateAngularRateHermite(int sample_count, const RateAt& rate_at,
                                 const std::vector<double>& step_s, T* rotation,
                                 std::vector<std::array<T, 4>>* path = nullptr) {
  T quaternion[4] = {T(1.0), T(0.0), T(0.0), T(0.0)};
  if (path != nullptr) path->assign(1, {T(1.0), T(0.0), T(0.0), T(0.0)});
  if (sample_count < 2) {
    QuaternionToRotationMatrix(quaternion, rotation);
    return;
  }
  // A window of four consecutive rates (j - 1 .. j + 2), clamped at the ends.
  auto slope = [&](int j, const T* before, const T* here, const T* after, T* out) {
    const int lo = j > 0 ? j - 1 : j;
    const int hi = j + 1 < sample_count ? j + 1 : j;
    double span = 0.0;
    for (int i = lo; i < hi; ++i) span += step_s[i];
    const T* a = j > 0 ? before : here;
    const T* b = j + 1 < sample_count ? after : here;
    for (int k = 0; k < 3; ++k) out[k] = (b[k] - a[k]) / T(span);
  };
  T w[4][3];  // rates j - 1, j, j + 1, j + 2
  rate_at(0, w[1]);
  rate_at(1, w[2]);
  for (int k = 0; k < 3; ++k) w[0][k] = w[1][k];
  if (sample_count > 2) {
    rate_at(2, w[3]);
  } else {
    for (int k = 0; k < 3; ++k) w[3][k] = w[2][k];
  }
  for (int j = 0; j + 1 < sample_count; ++j) {
    T slope_here[3], slope_next[3], middle[3];
    slope(j, w[0], w[1], w[2], slope_here);
    slope(j + 1, w[1], w[2], w[3], slope_next);
    const double dt = step_s[j];
    for (int k = 0; k < 3; ++k) {
      middle[k] = T(0.5) * (w[1][k] + w[2][k]) + T(dt / 8.0) * (slope_here[k] - slope_next[k]);
    }
    QuaternionRk4Step(w[1], middle, w[2], dt, quaternion);
    if (path != nullptr)
      path->push_back({quaternion[0], quaternion[1], quaternion[2], quaternion[3]});
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) w[i][k] = w[i + 1][k];
    if (j + 3 < sample_count) rate_at(j + 3, w[3]);
  }
  QuaternionToRotationMatrix(quaternion, rotation);
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_H_
