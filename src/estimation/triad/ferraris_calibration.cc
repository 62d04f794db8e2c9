#include "estimation/triad/ferraris_calibration.h"

#include <Eigen/Dense>
#include <cmath>

#include "common/format.h"

namespace accelcal {
namespace {

Eigen::Vector3d Vector(const std::array<double, 3>& values) {
  return Eigen::Vector3d(values[0], values[1], values[2]);
}

// Columns: the means of the holds of x, y, z, up (`up`) or down.
Eigen::Matrix3d HoldMeans(const FerrarisSession& session, bool up, bool gyroscope) {
  Eigen::Matrix3d means;
  for (int axis = 0; axis < 3; ++axis) {
    const FerrarisSectionData& hold = session[up ? FerrarisHoldUp(axis) : FerrarisHoldDown(axis)];
    means.col(axis) = Vector(gyroscope ? hold.gyroscope.mean : hold.accelerometer.mean);
  }
  return means;
}

Status Gyroscope(const FerrarisSession& session, const FerrarisOptions& options,
                 ImucalCalibration* calibration) {
  if (!(options.sampling_rate_hz > 0.0) || !std::isfinite(options.sampling_rate_hz)) {
    return Status::Error(StringPrintf(
        "sampling rate %g Hz: the turns are integrated at the session's sampling rate; give it "
        "(imucal's example: 204.8 Hz)",
        options.sampling_rate_hz));
  }
  if (!(options.expected_angle_deg != 0.0) || !std::isfinite(options.expected_angle_deg)) {
    return Status::Error(StringPrintf(
        "expected turn angle %g deg: each turn's angle must be non-zero (imucal: -360 for one "
        "clockwise turn)",
        options.expected_angle_deg));
  }
  const ImucalAccelerometer& acc = calibration->accelerometer;
  ImucalGyroscope& gyr = calibration->gyroscope;
  Eigen::Vector3d hold_sum = Eigen::Vector3d::Zero();
  double hold_samples = 0.0;
  for (int s = 0; s < kFerrarisHoldCount; ++s) {
    const TriadPoseMean& hold = session.sections[s].gyroscope;
    hold_sum += hold.sample_count * Vector(hold.mean);
    hold_samples += hold.sample_count;
  }
  gyr.b_g = hold_sum / hold_samples;
  gyr.k_ga = (HoldMeans(session, true, true) - HoldMeans(session, false, true)) /
             (2.0 * options.gravity_mps2);
  const Eigen::Matrix3d to_force = acc.r_a.inverse() * acc.k_a.inverse();
  Eigen::Matrix3d turns;
  for (int axis = 0; axis < 3; ++axis) {
    const FerrarisSectionData& turn = session[FerrarisTurn(axis)];
    const double n = turn.gyroscope.sample_count;
    const Eigen::Vector3d force_sum =
        to_force * (n * Vector(turn.accelerometer.mean) - n * acc.b_a);
    turns.col(axis) = (n * Vector(turn.gyroscope.mean) - gyr.k_ga * force_sum - n * gyr.b_g) /
                      options.sampling_rate_hz;
  }
  const Eigen::Matrix3d m = turns / options.expected_angle_deg;
  const Eigen::Vector3d norms = m.rowwise().norm();
  for (int k = 0; k < 3; ++k) {
    if (!(norms[k] > 0.0)) {
      return Status::Error(StringPrintf(
          "the gyroscope's %c axis integrates to zero over the three turns: it did not see them",
          "xyz"[k]));
    }
  }
  gyr.k_g = norms.asDiagonal();
  gyr.r_g = norms.cwiseInverse().asDiagonal() * m;
  calibration->has_gyroscope = true;
  return Status::Ok();
}

}  // namespace

double FerrarisHoldOrthogonality(const FerrarisSession& session) {
  const Eigen::Matrix3d difference =
      HoldMeans(session, true, false) - HoldMeans(session, false, false);
  const double norms =
      difference.col(0).norm() * difference.col(1).norm() * difference.col(2).norm();
  return norms > 0.0 ? difference.determinant() / norms : 0.0;
}

Status FerrarisClosedForm(const FerrarisSession& session, const FerrarisOptions& options,
                          ImucalCalibration* calibration) {
  *calibration = ImucalCalibration();
  if (!(options.gravity_mps2 > 0.0) || !std::isfinite(options.gravity_mps2)) {
    return Status::Error(StringPrintf("gravity %g m/s^2: must be positive", options.gravity_mps2));
  }
  const double orthogonality = FerrarisHoldOrthogonality(session);
  if (!(orthogonality >= options.min_hold_orthogonality)) {
    return Status::Error(StringPrintf(
        "the holds' axes (x_p - x_a, y_p - y_a, z_p - z_a) have a normalised determinant of "
        "%.3g, %s 1 for three orthogonal axes (at least %.2g accepted): %s",
        orthogonality, "while Ferraris's method assumes", options.min_hold_orthogonality,
        orthogonality < 0.0
            ? "they form a left-handed set; are two sections' labels swapped?"
            : "two holds point the same way or a pair's means coincide; check the labels and "
              "that each axis was held up and down"));
  }
  const Eigen::Matrix3d up = HoldMeans(session, true, false);
  const Eigen::Matrix3d down = HoldMeans(session, false, false);
  const Eigen::Matrix3d difference = up - down;
  ImucalAccelerometer& acc = calibration->accelerometer;
  acc.b_a = ((up + down) / 2.0).diagonal();
  // imucal's expression (Eq. 23 of its source), so that the rounding is the same.
  const Eigen::Vector3d gains =
      (difference.rowwise().squaredNorm() / (4.0 * options.gravity_mps2 * options.gravity_mps2))
          .cwiseSqrt();
  acc.k_a = gains.asDiagonal();
  acc.r_a = gains.cwiseInverse().asDiagonal() * difference / (2.0 * options.gravity_mps2);
  if (options.sampling_rate_hz == 0.0) return Status::Ok();
  return Gyroscope(session, options, calibration);
}

}  // namespace accelcal
