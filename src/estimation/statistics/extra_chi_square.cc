#include "estimation/statistics/extra_chi_square.h"

#include <Eigen/Dense>
#include <algorithm>
#include <vector>

namespace accelcal {

ModelSpan::ModelSpan(const Eigen::MatrixXd& model) {
  if (model.cols() == 0) {
    basis_.resize(model.rows(), 0);
    return;
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(model);
  basis_ = qr.householderQ() * Eigen::MatrixXd::Identity(model.rows(), model.cols());
}

Eigen::MatrixXd ModelSpan::Beside(const Eigen::MatrixXd& extra) const {
  Eigen::MatrixXd projected = extra;
  // Twice, for the columns nearly inside the model's span.
  if (basis_.cols() > 0)
    for (int pass = 0; pass < 2; ++pass) projected -= basis_ * (basis_.transpose() * projected);
  return projected;
}

double ModelSpan::ExtraChiSquare(const Eigen::MatrixXd& extra, const Eigen::VectorXd& r,
                                 int* rank) const {
  const Eigen::MatrixXd projected = Beside(extra);
  // Columns with (almost) nothing left outside the model's span add nothing.
  std::vector<int> kept;
  for (int c = 0; c < extra.cols(); ++c) {
    if (projected.col(c).squaredNorm() > 1e-10 * std::max(1e-300, extra.col(c).squaredNorm()))
      kept.push_back(c);
  }
  if (kept.empty()) {
    if (rank != nullptr) *rank = 0;
    return 0.0;
  }
  Eigen::MatrixXd columns(projected.rows(), kept.size());
  for (size_t c = 0; c < kept.size(); ++c) {
    columns.col(c) = projected.col(kept[c]) / projected.col(kept[c]).norm();
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(columns);
  qr.setThreshold(1e-8);
  const int added = static_cast<int>(qr.rank());
  if (rank != nullptr) *rank = added;
  if (added == 0) return 0.0;
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(columns.rows(), added);
  // r minus its part in the model's span (zero at an optimum, not exactly after rounding).
  return (q.transpose() * r).squaredNorm();
}

double ExtraChiSquare(const Eigen::MatrixXd& model, const Eigen::MatrixXd& extra,
                      const Eigen::VectorXd& r, int* rank) {
  return ModelSpan(model).ExtraChiSquare(extra, r, rank);
}

Eigen::VectorXd ProjectedCoefficients(const Eigen::MatrixXd& model, const Eigen::MatrixXd& extra,
                                      const Eigen::VectorXd& r) {
  Eigen::MatrixXd both(model.rows(), model.cols() + extra.cols());
  both << model, extra;
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> decomposition(both);
  const Eigen::VectorXd beta = decomposition.solve(r);
  return beta.tail(extra.cols());
}

}  // namespace accelcal
