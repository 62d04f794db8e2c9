#ifndef ACCELCAL_ESTIMATION_TRIAD_FERRARIS_CALIBRATION_H_
#define ACCELCAL_ESTIMATION_TRIAD_FERRARIS_CALIBRATION_H_

// imucal's Ferraris calibration in closed form (Ferraris et al., Sensors and Materials 1995,
// as imucal's FerrarisCalibration.compute implements it; docs/imucal.md), from the sections'
// means (common/ferraris_session.h), so that imucal's numbers are reproduced to rounding.
//
// Accelerometer. With U_p and U_n the 3x3 matrices whose columns are the means of the holds
// x_p, y_p, z_p and x_a, y_a, z_a (counts), and g the gravity (m/s^2):
//
//   b_a = diag((U_p + U_n) / 2)                   each axis's offset from its own pair only
//   U_d = U_p - U_n = 2 g K_a R_a                 (Ferraris's assumption: the holds are +-g
//   K_a = diag(|row_k(U_d)|) / (2 g)               along three orthogonal axes, exactly)
//   R_a = K_a^-1 U_d / (2 g)
//
// Gyroscope (deg/s; only with a sampling rate). b_g = the mean of every hold sample's output
// (holds weighted by their length, as imucal stacks them); K_ga = (G_p - G_n) / (2 g) with
// G_p, G_n the holds' gyroscope means as columns; for each turn r (about x, y, z), with N_r
// samples at f_s Hz, the integral of the corrected output
//
//   W_r = (sum_r u_g - K_ga R_a^-1 K_a^-1 (sum_r u_a - N_r b_a) - N_r b_g) / f_s
//
// (imucal corrects each sample; the correction is linear, so the sums give the same numbers),
// M = [W_x W_y W_z] / expected_angle_deg, K_g = diag(|row_k(M)|), R_g = K_g^-1 M.
//
// Refused (a Status, one line): holds whose pair differences are not a right-handed set of
// nearly orthogonal directions. Their normalised determinant det(U_d) / prod |col_k(U_d)|
// (1 for orthogonal holds) below `min_hold_orthogonality` means sections mislabelled or holds
// repeated, and a negative one holds listed in a mirrored order; a pair whose two means
// coincide has no direction at all.

#include "common/ferraris_session.h"
#include "common/status.h"
#include "models/imucal_convention.h"

namespace accelcal {

struct FerrarisOptions {
  double gravity_mps2 = 9.81;          // imucal's grav
  double expected_angle_deg = -360.0;  // imucal's expected_angle: each turn, signed
  double sampling_rate_hz = 0.0;       // of the session; 0: the accelerometer only
  double min_hold_orthogonality = 0.5;
};

// The holds' normalised determinant det(U_d) / prod_k |col_k(U_d)| (0 when a pair's means
// coincide).
double FerrarisHoldOrthogonality(const FerrarisSession& session);

Status FerrarisClosedForm(const FerrarisSession& session, const FerrarisOptions& options,
                          ImucalCalibration* calibration);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_FERRARIS_CALIBRATION_H_
