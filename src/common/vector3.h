#ifndef ACCELCAL_COMMON_VECTOR3_H_
#define ACCELCAL_COMMON_VECTOR3_H_

// The few operations on 3-vectors (std::array<double, 3>) that the gyroscope's fits, its checks
// and the simulator share: cross and dot products, and the angle between two directions.

#include <array>
#include <cmath>

namespace accelcal {

using Vector3 = std::array<double, 3>;

inline Vector3 Cross(const Vector3& a, const Vector3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

inline double Dot(const Vector3& a, const Vector3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// The angle between a and b (rad, in [0, pi]), accurate near 0 and pi (atan2 of |a x b| and
// a . b, not acos).
inline double AngleBetween(const Vector3& a, const Vector3& b) {
  const Vector3 c = Cross(a, b);
  return std::atan2(std::sqrt(Dot(c, c)), Dot(a, b));
}

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_VECTOR3_H_
