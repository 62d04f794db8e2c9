#ifndef ACCELCAL_MODELS_IMUCAL_CONVENTION_H_
#define ACCELCAL_MODELS_IMUCAL_CONVENTION_H_

// imucal's calibration (MaD-Lab, FAU; its FerrarisCalibrationInfo) and its mapping onto the
// triad model of models/triad.h (docs/imucal.md).
//
// imucal:    a = R_a^-1 K_a^-1 (u - b_a)        accelcal (imu_tk):  a' = T K (u - b)
//
// K_a diagonal (counts per m/s^2), R_a with unit-norm rows (the sensing axes as seen in the
// frame the Ferraris holds define), b_a the output at zero specific force (counts). Both map
// the raw output u to specific force in m/s^2, in two frames that differ by a rotation Q:
// a = Q a'. So R_a^-1 K_a^-1 = Q T K is the QR decomposition of imucal's matrix with the
// diagonal of the triangular factor positive (unique for an invertible matrix): K is that
// diagonal, T the factor with its columns divided by it, and b = b_a. The inverse direction
// needs Q (accelcal's frame carries no orientation): K_a R_a = (Q T K)^-1, whose row norms
// are K_a's diagonal.
//
// A rotation exists only when det(R_a) > 0: an R_a that mirrors the frame (holds labelled
// in a left-handed order, or gravity's sign flipped) is refused, saying so.
//
// The gyroscope: imucal's  w = R_g^-1 K_g^-1 (u_g - K_ga a - b_g)  (its gyr_unit, deg/s by
// default), a the calibrated acceleration; accelcal's (models/gyroscope.h)  w = T_g K_g (u_g - b_g)
// in rad/s, in the accelerometer's frame, with no term in a. In one frame the two agree with
// K_ga = 0, b_g = b and R_g^-1 K_g^-1 = c T_g K_g (c = 180/pi for deg/s, 1 for rad/s), which
// fixes K_g and R_g as for the accelerometer: K_g R_g = (c T_g K_g)^-1, K_g its row norms.

#include <Eigen/Core>

#include "common/status.h"
#include "models/gyroscope.h"
#include "models/triad.h"

namespace accelcal {

struct ImucalAccelerometer {
  Eigen::Matrix3d k_a = Eigen::Matrix3d::Identity();  // K_a, counts per m/s^2, diagonal
  Eigen::Matrix3d r_a = Eigen::Matrix3d::Identity();  // R_a, unit-norm rows
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();      // b_a, counts
};

struct ImucalGyroscope {
  Eigen::Matrix3d k_g = Eigen::Matrix3d::Identity();  // K_g, counts per deg/s, diagonal
  Eigen::Matrix3d r_g = Eigen::Matrix3d::Identity();  // R_g
  Eigen::Matrix3d k_ga = Eigen::Matrix3d::Zero();     // K_ga, counts per m/s^2
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();      // b_g, counts
};

// What imucal's FerrarisCalibrationInfo holds (its JSON's K_a, R_a, b_a, K_g, R_g, K_ga, b_g).
struct ImucalCalibration {
  ImucalAccelerometer accelerometer;
  bool has_gyroscope = false;
  ImucalGyroscope gyroscope;
};

// a = R_a^-1 K_a^-1 (u - b_a), m/s^2 in imucal's frame.
Eigen::Vector3d ImucalSpecificForce(const ImucalAccelerometer& imucal, const Eigen::Vector3d& raw);

// T K of models/triad.h as a matrix: a' = T K (u - b).
Eigen::Matrix3d TriadMatrix(const TriadParameters& triad);

// imucal -> accelcal: the triad's nine parameters and Q (a = Q a', a proper rotation). Fails
// when K_a is not diagonal with positive entries or when R_a is singular or mirrors the frame.
Status ImucalToTriad(const ImucalAccelerometer& imucal, TriadParameters* triad,
                     Eigen::Matrix3d* frame_rotation);

// accelcal -> imucal in the frame `frame_rotation` (Q) turns accelcal's into: K_a, R_a, b_a
// with R_a^-1 K_a^-1 = Q T K. With the Q that ImucalToTriad returned, the round trip gives
// back imucal's matrices.
ImucalAccelerometer TriadToImucal(const TriadParameters& triad,
                                  const Eigen::Matrix3d& frame_rotation);

// accelcal's gyroscope -> imucal's in accelcal's frame (that of TriadToImucal with Q = I):
// K_g, R_g (unit-norm rows), K_ga = 0 and b_g = `offset`, so that R_g^-1 K_g^-1 (u - b_g) is
// `output_per_radps` T_g K_g (u - b). `output_per_radps` is imucal's gyr_unit per rad/s: 1 for
// rad/s, 180/pi for deg/s.
ImucalGyroscope GyroscopeToImucal(const GyroscopeParameters& parameters,
                                  const GyroscopeOffset& offset, double output_per_radps);

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_IMUCAL_CONVENTION_H_
