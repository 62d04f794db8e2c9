#include "estimation/solver/identifiability.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "common/format.h"

namespace accelcal {

Status CheckIdentifiable(const Eigen::MatrixXd& information,
                         const std::vector<Parameter>& parameters, double threshold) {
  const int p = static_cast<int>(parameters.size());
  std::string unconstrained;
  for (int i = 0; i < p; ++i) {
    if (!(information(i, i) > 0.0)) {
      unconstrained += std::string(unconstrained.empty() ? "" : ", ") + Info(parameters[i]).name;
    }
  }
  if (!unconstrained.empty()) {
    std::string hint;
    for (const Parameter parameter : parameters) {
      if (ActsOnlyInRun(parameter)) {
        hint =
            "; an effect acting only in the run is observable only through a landmark (--landmark)";
      }
    }
    return Status::Error("not identifiable: no residual depends on " + unconstrained + hint);
  }
  const Eigen::VectorXd scale = information.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd normalized = scale.asDiagonal() * information * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(normalized);
  const double largest = eigen.eigenvalues().maxCoeff();
  for (int k = 0; k < p; ++k) {
    if (eigen.eigenvalues()[k] > threshold * largest) continue;
    std::string together;
    const Eigen::VectorXd direction = eigen.eigenvectors().col(k);
    for (int i = 0; i < p; ++i) {
      if (std::abs(direction[i]) > 0.1) {
        together += std::string(together.empty() ? "" : ", ") + Info(parameters[i]).name;
      }
    }
    // clang-format off
    return Status::Error(StringPrintf(
        "not identifiable: %s cannot be separated with these data (their information matrix has a near-null direction, eigenvalue ratio %.1e); fix one of them or change the test design",
        together.c_str(), eigen.eigenvalues()[k] / largest));
    // clang-format on
  }
  return Status::Ok();
}

}  // namespace accelcal
