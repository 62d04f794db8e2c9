#ifndef ACCELCAL_MODELS_TILT_TABLE_H_
#define ACCELCAL_MODELS_TILT_TABLE_H_

// The tilt-table test's true specific force (../shared/spec/error-model.md, "Frames and
// the tilt-table test"). The table is rotated through a reported angle theta_i in
// gravity; its zero may be off (the angle offset, models/effects/angle_offset.h, gives the
// true angle theta_true_i from the reported theta_i):
//
//   fx_i = -g sin(theta_true_i),  fy_i = -g cos(theta_true_i)   [m/s^2]
//
// Templated so the Ceres residuals (T = ceres::Jet), the closed-form estimator and the
// simulator (T = double) all evaluate the same expression.

#include <cmath>

namespace accelcal {

// Standard gravity used by the course (the assignment takes g = 9.8 m/s^2).
constexpr double kCourseGravityMps2 = 9.8;

// The force from the sine and cosine of the true angle, for callers that compute them in
// batches (common/sincos.h). T may also be a vector of doubles (GCC's vector extension), as
// in the closed-form estimator's block loop (estimation/tilt_table/linear_ls_accumulator.cc).
template <typename T>
inline void TiltTableSpecificForceFromSinCos(const T& sin_theta_true, const T& cos_theta_true,
                                             double gravity_mps2, T* specific_force_x,
                                             T* specific_force_y) {
  *specific_force_x = -gravity_mps2 * sin_theta_true;
  *specific_force_y = -gravity_mps2 * cos_theta_true;
}

template <typename T>
void TiltTableSpecificForce(const T& theta_true_rad, double gravity_mps2, T* specific_force_x,
                            T* specific_force_y) {
  using std::cos;
  using std::sin;
  TiltTableSpecificForceFromSinCos<T>(sin(theta_true_rad), cos(theta_true_rad), gravity_mps2,
                                      specific_force_x, specific_force_y);
}

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TILT_TABLE_H_
