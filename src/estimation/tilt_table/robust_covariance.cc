#include "estimation/tilt_table/robust_covariance.h"

#include <Eigen/LU>
#include <cmath>

#include "estimation/tilt_table/joint_data.h"

namespace accelcal {

Status HuberSandwichCovariance(const JointData& data, const JointOptions& options,
                               JointResult* result) {
  if (options.loss != RobustLoss::kHuber) {
    return Status::Error("the sandwich covariance is for a Huber fit");
  }
  Eigen::MatrixXd jacobian;
  Eigen::VectorXd residual;
  ACCELCAL_RETURN_IF_ERROR(LinearizeJoint(data, options, *result, &jacobian, &residual));
  const int p = static_cast<int>(jacobian.cols());
  const int calibration_rows = 2 * data.test().size();
  const double k = options.loss_scale;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(p, p);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(p, p);
  for (int row = 0; row < jacobian.rows(); ++row) {
    const Eigen::VectorXd j = jacobian.row(row).transpose();
    if (row >= calibration_rows) {  // the endpoint: no loss
      a.noalias() += j * j.transpose();
      b.noalias() += j * j.transpose();
      continue;
    }
    const double r = residual[row];
    const bool inside = std::abs(r) <= k;
    const double psi = inside ? r : std::copysign(k, r);
    if (inside) a.noalias() += j * j.transpose();
    b.noalias() += psi * psi * j * j.transpose();
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  if (!lu.isInvertible()) {
    return Status::Error(
        "the Huber fit's information matrix is singular: too few samples inside the loss's "
        "quadratic region");
  }
  const Eigen::MatrixXd a_inverse = lu.inverse();
  result->estimate.covariance = a_inverse * b * a_inverse;
  return Status::Ok();
}

}  // namespace accelcal
