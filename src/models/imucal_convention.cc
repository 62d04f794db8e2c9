#include "models/imucal_convention.h"

#include <Eigen/Dense>
#include <cmath>

#include "common/format.h"

namespace accelcal {

Eigen::Vector3d ImucalSpecificForce(const ImucalAccelerometer& imucal, const Eigen::Vector3d& raw) {
  // K_a R_a a = u - b_a, solved rather than inverted twice.
  return (imucal.k_a * imucal.r_a).partialPivLu().solve(raw - imucal.b_a);
}

Eigen::Matrix3d TriadMatrix(const TriadParameters& triad) {
  Eigen::Matrix3d t;
  t << 1.0, -triad[kTriadMisalignmentYz], triad[kTriadMisalignmentZy],  //
      0.0, 1.0, -triad[kTriadMisalignmentZx],                           //
      0.0, 0.0, 1.0;
  const Eigen::Vector3d gains(triad[kTriadGainX], triad[kTriadGainY], triad[kTriadGainZ]);
  return t * gains.asDiagonal();
}

Status ImucalToTriad(const ImucalAccelerometer& imucal, TriadParameters* triad,
                     Eigen::Matrix3d* frame_rotation) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double k = imucal.k_a(i, j);
      if (i != j && k != 0.0) {
        return Status::Error(StringPrintf(
            "K_a[%d][%d] = %g: imucal's K_a is diagonal; a full matrix is not its convention", i, j,
            k));
      }
      if (i == j && !(k > 0.0 && std::isfinite(k))) {
        return Status::Error(StringPrintf(
            "K_a[%d][%d] = %g: the gains must be positive and finite (counts per m/s^2)", i, i, k));
      }
    }
  }
  const double determinant = imucal.r_a.determinant();
  if (!(determinant > 0.0) || !imucal.r_a.allFinite()) {
    return Status::Error(StringPrintf(
        "R_a has determinant %g: %s; no rotation maps imucal's frame onto accelcal's (check that "
        "the holds x_p..z_a are labelled with the axis pointing up, and the sign of gravity)",
        determinant, determinant < 0.0 ? "it mirrors the frame" : "it is singular"));
  }
  // imucal's matrix M = R_a^-1 K_a^-1 = Q U, U upper triangular with a positive diagonal.
  const Eigen::Matrix3d m =
      imucal.r_a.inverse() * imucal.k_a.diagonal().cwiseInverse().asDiagonal();
  const Eigen::HouseholderQR<Eigen::Matrix3d> qr(m);
  Eigen::Matrix3d q = qr.householderQ();
  Eigen::Matrix3d u = qr.matrixQR().triangularView<Eigen::Upper>();
  for (int i = 0; i < 3; ++i) {
    if (u(i, i) < 0.0) {
      u.row(i) *= -1.0;
      q.col(i) *= -1.0;
    }
  }
  TriadParameters& p = *triad;
  p[kTriadGainX] = u(0, 0);
  p[kTriadGainY] = u(1, 1);
  p[kTriadGainZ] = u(2, 2);
  // T = U K^-1: each column divided by its gain; T's entries are the angles themselves.
  p[kTriadMisalignmentYz] = -u(0, 1) / u(1, 1);
  p[kTriadMisalignmentZy] = u(0, 2) / u(2, 2);
  p[kTriadMisalignmentZx] = -u(1, 2) / u(2, 2);
  p[kTriadOffsetX] = imucal.b_a[0];
  p[kTriadOffsetY] = imucal.b_a[1];
  p[kTriadOffsetZ] = imucal.b_a[2];
  *frame_rotation = q;
  return Status::Ok();
}

ImucalAccelerometer TriadToImucal(const TriadParameters& triad,
                                  const Eigen::Matrix3d& frame_rotation) {
  // K_a R_a = (Q T K)^-1: K_a's diagonal is the row norms, R_a the rows made unit.
  const Eigen::Matrix3d inverse = (frame_rotation * TriadMatrix(triad)).inverse();
  ImucalAccelerometer imucal;
  const Eigen::Vector3d norms = inverse.rowwise().norm();
  imucal.k_a = norms.asDiagonal();
  imucal.r_a = norms.cwiseInverse().asDiagonal() * inverse;
  imucal.b_a = Eigen::Vector3d(triad[kTriadOffsetX], triad[kTriadOffsetY], triad[kTriadOffsetZ]);
  return imucal;
}

ImucalGyroscope GyroscopeToImucal(const GyroscopeParameters& parameters,
                                  const GyroscopeOffset& offset, double output_per_radps) {
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> misalignment;
  GyroscopeMisalignmentMatrix(parameters.data(), misalignment.data());
  const Eigen::Vector3d gains(parameters[kGyroscopeGainX], parameters[kGyroscopeGainY],
                              parameters[kGyroscopeGainZ]);
  const Eigen::Matrix3d matrix = output_per_radps * misalignment * gains.asDiagonal();
  // K_g R_g = (c T_g K_g)^-1, as the accelerometer's.
  const Eigen::Matrix3d inverse = matrix.inverse();
  const Eigen::Vector3d norms = inverse.rowwise().norm();
  ImucalGyroscope imucal;
  imucal.k_g = norms.asDiagonal();
  imucal.r_g = norms.cwiseInverse().asDiagonal() * inverse;
  imucal.k_ga = Eigen::Matrix3d::Zero();
  imucal.b_g = Eigen::Vector3d(offset[0], offset[1], offset[2]);
  return imucal;
}

}  // namespace accelcal
