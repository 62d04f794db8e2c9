#include "estimation/triad/triad_identifiability.h"

#include <ceres/crs_matrix.h>

#include <Eigen/Dense>
#include <cmath>

namespace accelcal {
namespace {

constexpr char kDirectionsOnly[] = "the gravity directions of some poses";

// The parameters whose rows of an orthonormal basis of the null space have a norm above 0.1.
std::vector<std::string> NamesInNullSpace(const Eigen::MatrixXd& null_space,
                                          const std::vector<std::string>& parameter_names) {
  std::vector<std::string> names;
  for (size_t p = 0; p < parameter_names.size(); ++p) {
    if (null_space.row(static_cast<int>(p)).norm() > 0.1) names.push_back(parameter_names[p]);
  }
  if (names.empty()) names.push_back(kDirectionsOnly);
  return names;
}

}  // namespace

bool TriadArrowJacobianFromCrs(const ceres::CRSMatrix& crs, int sensor_columns,
                               TriadArrowJacobian* jacobian) {
  const int pose_count = crs.num_rows / 3;
  if (crs.num_rows != 3 * pose_count || crs.num_cols != sensor_columns + 2 * pose_count)
    return false;
  jacobian->sensor = Eigen::MatrixXd::Zero(crs.num_rows, sensor_columns);
  jacobian->direction = Eigen::MatrixXd::Zero(crs.num_rows, 2);
  for (int row = 0; row < crs.num_rows; ++row) {
    const int pose = row / 3;
    for (int i = crs.rows[row]; i < crs.rows[row + 1]; ++i) {
      const int column = crs.cols[i];
      if (column < sensor_columns) {
        jacobian->sensor(row, column) = crs.values[i];
      } else {
        const int local = column - sensor_columns - 2 * pose;
        if (local < 0 || local > 1) {
          if (crs.values[i] != 0.0) return false;
          continue;
        }
        jacobian->direction(row, local) = crs.values[i];
      }
    }
  }
  return true;
}

TriadReducedInformation ReducedInformation(const TriadArrowJacobian& jacobian) {
  const int sensor_columns = static_cast<int>(jacobian.sensor.cols());
  const int pose_count = jacobian.pose_count();
  TriadReducedInformation reduced;
  reduced.information = Eigen::MatrixXd::Zero(sensor_columns, sensor_columns);
  reduced.column_norms = jacobian.sensor.colwise().norm().transpose();
  reduced.q.resize(pose_count);
  Eigen::VectorXd a(sensor_columns);
  for (int p = 0; p < pose_count; ++p) {
    const Eigen::Vector3d b1 = jacobian.direction.block<3, 1>(3 * p, 0);
    const Eigen::Vector3d b2 = jacobian.direction.block<3, 1>(3 * p, 1);
    const Eigen::Vector3d normal = b1.cross(b2);
    const double norm = normal.norm();
    if (!(norm > 1e-12 * b1.norm() * b2.norm())) {
      reduced.directions_determined = false;
      reduced.q[p].setZero();
      continue;
    }
    reduced.q[p] = normal / norm;
    a.noalias() = jacobian.sensor.middleRows<3>(3 * p).transpose() * reduced.q[p];
    reduced.information.noalias() += a * a.transpose();
  }
  return reduced;
}

std::vector<std::string> UnidentifiableParametersWhole(
    const TriadArrowJacobian& arrow, const std::vector<std::string>& parameter_names,
    double rank_tolerance) {
  const int sensor_columns = static_cast<int>(arrow.sensor.cols());
  const int pose_count = arrow.pose_count();
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(3 * pose_count, sensor_columns + 2 * pose_count);
  jacobian.leftCols(sensor_columns) = arrow.sensor;
  for (int p = 0; p < pose_count; ++p)
    jacobian.block<3, 2>(3 * p, sensor_columns + 2 * p) = arrow.direction.middleRows<3>(3 * p);
  Eigen::VectorXd norms = jacobian.colwise().norm().transpose();
  const double largest_norm = norms.maxCoeff();
  for (int c = 0; c < jacobian.cols(); ++c) {
    // A column of zeros is a parameter nothing depends on: left at zero, it is in the null space.
    if (norms[c] > 1e-300 * largest_norm) jacobian.col(c) /= norms[c];
  }
  // The usual case, full rank, from the eigenvalues of J^T J alone (the squared singular
  // values; the tolerance's 1e-8 in squares is far above rounding): a tenth of the SVD's cost.
  const Eigen::MatrixXd normal = jacobian.transpose() * jacobian;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(normal, Eigen::EigenvaluesOnly);
  const Eigen::VectorXd& squared = eigen.eigenvalues();  // ascending
  if (squared[0] > 4.0 * rank_tolerance * rank_tolerance * squared[squared.size() - 1]) return {};
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeFullV);
  const Eigen::VectorXd& singular = svd.singularValues();
  int rank = 0;
  for (int i = 0; i < singular.size(); ++i)
    if (singular[i] > rank_tolerance * singular[0]) ++rank;
  const int nullity = static_cast<int>(jacobian.cols()) - rank;
  if (nullity == 0) return {};
  return NamesInNullSpace(svd.matrixV().rightCols(nullity), parameter_names);
}

std::vector<std::string> UnidentifiableParametersReduced(
    const TriadArrowJacobian& jacobian, const TriadReducedInformation& reduced,
    const std::vector<std::string>& parameter_names, double rank_tolerance) {
  if (!reduced.directions_determined)
    return UnidentifiableParametersWhole(jacobian, parameter_names, rank_tolerance);
  const int sensor_columns = static_cast<int>(jacobian.sensor.cols());
  const int pose_count = jacobian.pose_count();
  // Column scaling: D^-1 I_s D^-1 (a column of zeros, nothing depends on it, left unscaled).
  const double largest_norm = reduced.column_norms.maxCoeff();
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(sensor_columns);
  for (int c = 0; c < sensor_columns; ++c) {
    if (reduced.column_norms[c] > 1e-300 * largest_norm) scale[c] = 1.0 / reduced.column_norms[c];
  }
  const Eigen::MatrixXd normalised = scale.asDiagonal() * reduced.information * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(normalised);
  const Eigen::VectorXd& squared = eigen.eigenvalues();  // ascending: squared singular values
  const double threshold = rank_tolerance * rank_tolerance * squared[sensor_columns - 1];
  int nullity = 0;
  while (nullity < sensor_columns && !(squared[nullity] > threshold)) ++nullity;
  if (nullity == 0) return {};
  // Each null vector x~_s of the normalised sensor columns, extended to the directions as the
  // whole Jacobian's null vector (normalised coordinates: x~ = D x), then an orthonormal basis
  // of their span, whose first rows weigh the sensor parameters as the whole SVD's V did.
  Eigen::MatrixXd extended = Eigen::MatrixXd::Zero(sensor_columns + 2 * pose_count, nullity);
  for (int k = 0; k < nullity; ++k) {
    const Eigen::VectorXd x_normalised = eigen.eigenvectors().col(k);
    extended.col(k).head(sensor_columns) = x_normalised;
    const Eigen::VectorXd x = scale.asDiagonal() * x_normalised;  // unscaled sensor step
    for (int p = 0; p < pose_count; ++p) {
      const Eigen::Matrix<double, 3, 2> b = jacobian.direction.middleRows<3>(3 * p);
      const Eigen::Vector3d moved = jacobian.sensor.middleRows<3>(3 * p) * x;
      // x_d = -(B^T B)^-1 B^T A x_s, then scaled by the direction columns' norms.
      const Eigen::Vector2d x_d = -(b.transpose() * b).ldlt().solve(b.transpose() * moved);
      extended(sensor_columns + 2 * p, k) = x_d[0] * b.col(0).norm();
      extended(sensor_columns + 2 * p + 1, k) = x_d[1] * b.col(1).norm();
    }
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(extended);
  const Eigen::MatrixXd basis =
      qr.householderQ() * Eigen::MatrixXd::Identity(extended.rows(), nullity);
  return NamesInNullSpace(basis, parameter_names);
}

bool ReducedCovariance(const TriadReducedInformation& reduced, Eigen::MatrixXd* covariance) {
  const int sensor_columns = static_cast<int>(reduced.information.rows());
  Eigen::VectorXd scale(sensor_columns);
  for (int c = 0; c < sensor_columns; ++c) {
    if (!(reduced.column_norms[c] > 0.0)) return false;
    scale[c] = 1.0 / reduced.column_norms[c];
  }
  const Eigen::MatrixXd normalised = scale.asDiagonal() * reduced.information * scale.asDiagonal();
  const Eigen::LLT<Eigen::MatrixXd> llt(normalised);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd inverse =
      llt.solve(Eigen::MatrixXd::Identity(sensor_columns, sensor_columns));
  *covariance = scale.asDiagonal() * inverse * scale.asDiagonal();
  return covariance->allFinite();
}

}  // namespace accelcal
