#include "estimation/triad_ml_calibration.h"

#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>

#include "common/format.h"
#include "estimation/chi_square.h"
#include "residuals/triad_pose_residual.h"

namespace accelcal {
namespace {

constexpr int kMinPoses = kTriadParameterCount + 1;  // at least one degree of freedom

// s_k^2 pooled over the poses, weighted by their N_p - 1 degrees of freedom.
Status PooledNoiseVariance(const std::vector<TriadPoseMean>& poses, std::array<double, 3>* pooled) {
  std::array<double, 3> sum{};
  double weight = 0.0;
  for (const TriadPoseMean& pose : poses) {
    if (pose.sample_count < 2) {
      return Status::Error(StringPrintf(
          "a pose of %d sample(s) has no sample variance; every pose needs at least 2 samples",
          pose.sample_count));
    }
    for (int k = 0; k < 3; ++k) sum[k] += (pose.sample_count - 1) * pose.variance[k];
    weight += pose.sample_count - 1;
  }
  for (int k = 0; k < 3; ++k) {
    (*pooled)[k] = sum[k] / weight;
    if (!((*pooled)[k] > 0.0) || !std::isfinite((*pooled)[k])) {
      return Status::Error(StringPrintf(
          "the output of axis %c does not vary within any pose (pooled variance %g); the white "
          "noise model needs a noise to weight the residuals by",
          "xyz"[k], (*pooled)[k]));
    }
  }
  return Status::Ok();
}

// The directions of parameter space the poses do not determine: the right singular vectors of
// the column-normalised Jacobian (so that counts, rad and (m/s^2)/count compare) whose singular
// values are below rank_tolerance times the largest. Returns the names of the triad
// parameters with a weight above 0.1 in that null space, empty when the Jacobian has full rank.
std::vector<std::string> UnidentifiableParameters(const ceres::CRSMatrix& crs,
                                                  double rank_tolerance) {
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int i = crs.rows[row]; i < crs.rows[row + 1]; ++i)
      jacobian(row, crs.cols[i]) = crs.values[i];
  }
  Eigen::VectorXd norms = jacobian.colwise().norm().transpose();
  const double largest_norm = norms.maxCoeff();
  for (int c = 0; c < jacobian.cols(); ++c) {
    // A column of zeros is a parameter nothing depends on: left at zero, it is in the null space.
    if (norms[c] > 1e-300 * largest_norm) jacobian.col(c) /= norms[c];
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeFullV);
  const Eigen::VectorXd& singular = svd.singularValues();
  int rank = 0;
  for (int i = 0; i < singular.size(); ++i)
    if (singular[i] > rank_tolerance * singular[0]) ++rank;
  std::vector<std::string> names;
  const int nullity = static_cast<int>(jacobian.cols()) - rank;
  if (nullity == 0) return names;
  const Eigen::MatrixXd null_space = svd.matrixV().rightCols(nullity);
  for (int p = 0; p < kTriadParameterCount; ++p) {
    if (null_space.row(p).norm() > 0.1) names.push_back(TriadParameterInfos()[p].name);
  }
  if (names.empty()) names.push_back("the gravity directions of some poses");
  return names;
}

// When the directions lie near a plane: its normal, to say which poses to add.
std::string PlanarHint(const std::vector<std::array<double, 3>>& directions) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& d : directions) {
    const Eigen::Vector3d n(d[0], d[1], d[2]);
    scatter += n * n.transpose();
  }
  scatter /= static_cast<double>(directions.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
  // Smallest eigenvalue of the scatter: the mean squared out-of-plane component (0.01: about 6
  // deg).
  if (eigen.eigenvalues()[0] > 1e-2) return "";
  const Eigen::Vector3d normal = eigen.eigenvectors().col(0);
  return StringPrintf(
      "; the gravity directions of all poses lie within a few degrees of a plane (normal (%.3f, "
      "%.3f, %.3f) in the "
      "sensor frame: the sensor was only turned about that axis); add poses with gravity along "
      "or near it",
      normal[0], normal[1], normal[2]);
}

// Evaluates the whitened residuals and their Jacobian (in the directions' tangent space) and
// refuses, naming the parameters, when the Jacobian is rank-deficient.
Status CheckIdentifiable(double rank_tolerance, const std::vector<double*>& blocks,
                         const std::vector<ceres::ResidualBlockId>& residual_blocks,
                         const std::vector<std::array<double, 3>>& directions,
                         ceres::Problem* problem, std::vector<double>* residuals) {
  const int pose_count = static_cast<int>(directions.size());
  ceres::Problem::EvaluateOptions evaluate_options;
  evaluate_options.parameter_blocks = blocks;
  evaluate_options.residual_blocks = residual_blocks;
  double cost = 0.0;
  std::vector<double> values;
  ceres::CRSMatrix jacobian;
  if (!problem->Evaluate(evaluate_options, &cost, &values, nullptr, &jacobian)) {
    return Status::Error("the residuals could not be evaluated at the parameters reached");
  }
  CHECK_EQ(jacobian.num_cols, kTriadParameterCount + 2 * pose_count);
  if (residuals != nullptr) *residuals = values;
  const std::vector<std::string> unidentifiable =
      UnidentifiableParameters(jacobian, rank_tolerance);
  if (unidentifiable.empty()) return Status::Ok();
  std::string names;
  for (const std::string& name : unidentifiable) names += (names.empty() ? "" : ", ") + name;
  return Status::Error(StringPrintf(
      "the %d poses cannot determine the triad: %s not identifiable (the Jacobian of the "
      "%d residuals in the %d unknowns is rank-deficient)%s",
      pose_count, (names + (unidentifiable.size() == 1 ? " is" : " are")).c_str(), 3 * pose_count,
      kTriadParameterCount + 2 * pose_count, PlanarHint(directions).c_str()));
}

}  // namespace

std::vector<TriadPoseMean> PoseMeansOfIntervals(const TriadLog& log,
                                                const std::vector<StaticInterval>& intervals,
                                                int min_samples) {
  std::vector<TriadPoseMean> poses;
  for (const StaticInterval& interval : intervals) {
    if (interval.sample_count() < min_samples) continue;
    TriadPoseMean pose;
    pose.mean = IntervalMean(log, interval.start, interval.end);
    pose.variance = IntervalVariance(log, interval.start, interval.end);
    pose.sample_count = interval.sample_count();
    poses.push_back(pose);
  }
  return poses;
}

Status CalibrateTriadMl(const std::vector<TriadPoseMean>& poses, const TriadMlOptions& options,
                        TriadMlResult* result) {
  *result = TriadMlResult();
  const int pose_count = static_cast<int>(poses.size());
  result->pose_count = pose_count;
  if (pose_count < 1) return Status::Error("no static poses to calibrate from");
  ACCELCAL_RETURN_IF_ERROR(PooledNoiseVariance(poses, &result->noise_variance));

  // Initial directions: the initial calibration's specific force of each mean, normalised.
  result->parameters = options.initial;
  result->directions.resize(pose_count);
  for (int p = 0; p < pose_count; ++p) {
    double force[3];
    TriadSpecificForce(options.initial.data(), poses[p].mean.data(), force);
    const double norm = std::sqrt(force[0] * force[0] + force[1] * force[1] + force[2] * force[2]);
    if (!(norm > 0.0) || !std::isfinite(norm)) {
      return Status::Error(StringPrintf(
          "pose %d: the initial calibration maps its mean to a specific force of norm %g; give "
          "an initial bias near the output at zero specific force",
          p + 1, norm));
    }
    for (int k = 0; k < 3; ++k) result->directions[p][k] = force[k] / norm;
  }

  ceres::Problem problem;
  std::vector<ceres::ResidualBlockId> residual_blocks;
  std::vector<double*> blocks = {result->parameters.data()};
  for (int p = 0; p < pose_count; ++p) {
    std::array<double, 3> mean_stddev;
    for (int k = 0; k < 3; ++k)
      mean_stddev[k] = std::sqrt(result->noise_variance[k] / poses[p].sample_count);
    residual_blocks.push_back(problem.AddResidualBlock(
        TriadPoseResidual::Create(poses[p].mean, mean_stddev, options.gravity_mps2), nullptr,
        result->parameters.data(), result->directions[p].data()));
    problem.SetManifold(result->directions[p].data(), new ceres::SphereManifold<3>());
    blocks.push_back(result->directions[p].data());
  }

  // The rank check at the initial guess first: a rank-deficient problem wanders along its null
  // space while solving, which blurs what the poses cannot determine (and the plane they lie in).
  ACCELCAL_RETURN_IF_ERROR(CheckIdentifiable(options.rank_tolerance, blocks, residual_blocks,
                                             result->directions, &problem, nullptr));
  // A failed solve is reported after the rank check: a rank-deficient problem often does not
  // converge, and naming what cannot be determined is the more useful refusal.
  const Status solved = SolveQuietly(options.solve, &problem, &result->solver);

  // At the solution: the whitened residuals, and the rank check again (the initial guess may
  // have hidden a degeneracy).
  std::vector<double> residuals;
  ACCELCAL_RETURN_IF_ERROR(CheckIdentifiable(options.rank_tolerance, blocks, residual_blocks,
                                             result->directions, &problem, &residuals));
  result->whitened_residuals.resize(pose_count);
  result->chi2 = 0.0;
  for (int p = 0; p < pose_count; ++p) {
    for (int k = 0; k < 3; ++k) {
      result->whitened_residuals[p][k] = residuals[3 * p + k];
      result->chi2 += residuals[3 * p + k] * residuals[3 * p + k];
    }
  }
  ACCELCAL_RETURN_IF_ERROR(solved.WithContext("the maximum-likelihood solve"));
  if (pose_count < kMinPoses) {
    return Status::Error(StringPrintf(
        "%d poses give %d residuals for %d unknowns (9 parameters and 2 per gravity direction), "
        "%d degrees of freedom: nothing is left to check the noise model; hold the sensor in at "
        "least %d poses",
        pose_count, 3 * pose_count, kTriadParameterCount + 2 * pose_count,
        pose_count - kTriadParameterCount, kMinPoses));
  }

  ceres::Covariance::Options covariance_options;
  // Sparse QR, not dense SVD: under gcc's AddressSanitizer, Ceres' DENSE_SVD path (Eigen's
  // BDCSVD) frees memory it did not allocate (an allocator mismatch between the prebuilt
  // libceres and this build's Eigen), and the rank is checked above anyway.
  covariance_options.algorithm_type = ceres::SPARSE_QR;
  covariance_options.num_threads = 1;
  ceres::Covariance covariance(covariance_options);
  const std::vector<std::pair<const double*, const double*>> pairs = {
      {result->parameters.data(), result->parameters.data()}};
  if (!covariance.Compute(pairs, &problem)) {
    return Status::Error(
        "ceres::Covariance could not invert the information of the 9 triad parameters; the "
        "poses do not determine them");
  }
  double block[kTriadParameterCount * kTriadParameterCount];
  covariance.GetCovarianceBlock(result->parameters.data(), result->parameters.data(), block);
  for (int i = 0; i < kTriadParameterCount; ++i) {
    for (int j = 0; j < kTriadParameterCount; ++j)
      result->covariance[i][j] = block[i * kTriadParameterCount + j];
    result->stddev[i] = std::sqrt(result->covariance[i][i]);
  }

  result->degrees_of_freedom = pose_count - kTriadParameterCount;
  const double dof = result->degrees_of_freedom;
  result->chi2_per_dof = result->chi2 / dof;
  result->chi2_per_dof_spread = std::sqrt(2.0 / dof);
  result->p_value = ChiSquareSurvival(result->chi2, dof);
  return Status::Ok();
}

}  // namespace accelcal
