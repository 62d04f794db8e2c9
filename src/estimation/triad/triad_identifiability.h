#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_IDENTIFIABILITY_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_IDENTIFIABILITY_H_

// What the poses of the triad's maximum-likelihood problem (triad_ml_calibration.h) determine,
// from its arrow structure (issue 36): pose p's 3 whitened residuals depend on the S sensor
// parameters (the 9 of models/triad.h and the estimated effect coefficients, Jacobian A_p,
// 3 x S) and on its own gravity direction alone (2 tangent coordinates, Jacobian B_p, 3 x 2).
// Eliminating the directions leaves the sensor parameters' REDUCED information
//
//   I_s = sum_p A_p^T (1 - B_p (B_p^T B_p)^-1 B_p^T) A_p = sum_p (A_p^T q_p) (A_p^T q_p)^T,
//
// q_p the unit normal to B_p's columns (the residual direction the pose's own direction
// cannot absorb): S x S, built in one pass over the poses. Its inverse is the sensor parameters'
// block of the inverse of the whole information (the same marginal covariance ceres::Covariance
// computes over every block), and its null space is the whole Jacobian's null space restricted
// to the sensor parameters (a pose's direction follows x_s as x_d = -(B^T B)^-1 B^T A x_s).
//
// Rank: the singular values of the reduced column-normalised Jacobian (rows q_p^T A_p D^-1, D
// the sensor columns' norms in the whole Jacobian), i.e. the square roots of the eigenvalues of
// D^-1 I_s D^-1, below rank_tolerance times the largest. The parameters named are those with a
// weight above 0.1 in the null space of the whole column-normalised Jacobian, each null vector
// extended to the directions (x_d above) before the weights are taken, as the whole Jacobian's
// SVD gave them.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ceres {
struct CRSMatrix;
}

namespace accelcal {

// The Jacobian of the triad's ML problem by pose: rows 3p..3p+2 are pose p's residuals.
struct TriadArrowJacobian {
  Eigen::MatrixXd sensor;     // 3P x S: A_p stacked
  Eigen::MatrixXd direction;  // 3P x 2: B_p stacked
  int pose_count() const { return static_cast<int>(direction.rows() / 3); }
};

// From the Jacobian of the residuals of P poses (in pose order) with respect to the sensor
// blocks (S columns first) and then each pose's direction (2 columns each, in pose order), as
// ceres::Problem::Evaluate returns it. False when an entry lies outside that pattern.
bool TriadArrowJacobianFromCrs(const ceres::CRSMatrix& crs, int sensor_columns,
                               TriadArrowJacobian* jacobian);

struct TriadReducedInformation {
  Eigen::MatrixXd information;     // S x S, I_s (unscaled)
  Eigen::VectorXd column_norms;    // S: the sensor columns' norms in the whole Jacobian
  std::vector<Eigen::Vector3d> q;  // q_p per pose
  // False when some pose's direction block has not rank 2 (|b1 x b2| below 1e-12 |b1| |b2|):
  // then its direction is itself undetermined and only the whole Jacobian's SVD tells what.
  bool directions_determined = true;
};

TriadReducedInformation ReducedInformation(const TriadArrowJacobian& jacobian);

// The names (parameter_names: one per sensor column) of the parameters in the null space, as
// above; "the gravity directions of some poses" when the null space has none of them above
// 0.1; empty when the reduced information has full rank. Falls back to the whole Jacobian's
// SVD when !directions_determined.
std::vector<std::string> UnidentifiableParametersReduced(
    const TriadArrowJacobian& jacobian, const TriadReducedInformation& reduced,
    const std::vector<std::string>& parameter_names, double rank_tolerance);

// The same decision from the SVD of the whole dense column-normalised Jacobian (sensor columns
// then 2 per pose), its singular values below rank_tolerance times the largest: what accelcal
// did before issue 36, O(P^3); kept for the fallback above and to check the reduced rule.
std::vector<std::string> UnidentifiableParametersWhole(
    const TriadArrowJacobian& jacobian, const std::vector<std::string>& parameter_names,
    double rank_tolerance);

// The sensor parameters' covariance, I_s^-1 (computed on the column-normalised matrix); false
// when I_s is not positive definite.
bool ReducedCovariance(const TriadReducedInformation& reduced, Eigen::MatrixXd* covariance);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_IDENTIFIABILITY_H_
