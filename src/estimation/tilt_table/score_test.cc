#include "estimation/tilt_table/score_test.h"

#include <Eigen/QR>
#include <cmath>

#include "estimation/tilt_table/joint_data.h"

namespace accelcal {

Status ScoreCandidates(const JointData& data, const JointOptions& options,
                       const JointResult& current, const std::vector<Parameter>& candidates,
                       std::vector<double>* delta_chi2) {
  std::vector<Parameter> columns = current.estimate.free;
  columns.insert(columns.end(), candidates.begin(), candidates.end());
  Eigen::MatrixXd jacobian;
  Eigen::VectorXd r;
  ACCELCAL_RETURN_IF_ERROR(LinearizeJoint(data, options, current, &jacobian, &r, &columns));
  const int a = static_cast<int>(current.estimate.free.size());
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(jacobian.leftCols(a));
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(jacobian.rows(), a);
  delta_chi2->assign(candidates.size(), 0.0);
  for (size_t c = 0; c < candidates.size(); ++c) {
    const Eigen::VectorXd column = jacobian.col(a + static_cast<int>(c));
    const Eigen::VectorXd e = column - q * (q.transpose() * column);
    const double energy = e.squaredNorm();
    if (energy > 1e-12 * column.squaredNorm() && energy > 0.0)
      (*delta_chi2)[c] = std::pow(e.dot(r), 2) / energy;
  }
  return Status::Ok();
}

}  // namespace accelcal
