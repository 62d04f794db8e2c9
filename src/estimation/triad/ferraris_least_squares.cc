#include "estimation/triad/ferraris_least_squares.h"

#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>
#include <vector>

#include "common/format.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "residuals/ferraris_hold_residual.h"
#include "residuals/triad_pose_residual.h"

namespace accelcal {
namespace {

using Vector3 = std::array<double, 3>;

// The holds' means and their standard deviations under the pooled noise model.
struct HoldData {
  std::array<Vector3, kFerrarisHoldCount> mean{};
  std::array<Vector3, kFerrarisHoldCount> mean_stddev{};
};

Status PrepareHolds(const FerrarisSession& session, HoldData* holds, Vector3* pooled) {
  std::vector<TriadPoseMean> accelerometer;
  for (int p = 0; p < kFerrarisHoldCount; ++p) {
    const TriadPoseMean& hold = session.sections[p].accelerometer;
    if (hold.sample_count < 2) {
      return Status::Error(StringPrintf(
          "hold %s has %d sample(s), no spread to estimate the noise from; hold each position "
          "for at least a second",
          kFerrarisSectionLabels[p], hold.sample_count));
    }
    accelerometer.push_back(hold);
  }
  // The noise model of the maximum-likelihood triad fit, pooled over the six holds.
  *pooled = PooledWithinPoseVariance(accelerometer);
  for (int k = 0; k < 3; ++k) {
    if (!((*pooled)[k] > 0.0) || !std::isfinite((*pooled)[k])) {
      return Status::Error(StringPrintf(
          "the accelerometer's %c output does not vary within any hold (pooled variance %g): "
          "no noise to weight the least-squares residuals by",
          "xyz"[k], (*pooled)[k]));
    }
  }
  for (int p = 0; p < kFerrarisHoldCount; ++p) {
    const TriadPoseMean& hold = session.sections[p].accelerometer;
    holds->mean[p] = hold.mean;
    for (int k = 0; k < 3; ++k)
      holds->mean_stddev[p][k] = std::sqrt((*pooled)[k] / hold.sample_count);
  }
  return Status::Ok();
}

// Hold p's gravity under Ferraris's assumption: +-e_axis in imucal's frame.
Eigen::Vector3d HoldAxis(int p) { return (p % 2 == 0 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(p / 2); }

Status Covariance(ceres::Problem* problem, const std::vector<std::pair<double*, int>>& blocks,
                  std::vector<Eigen::MatrixXd>* covariances) {
  ceres::Covariance::Options covariance_options;
  // Sparse QR as in estimation/triad/triad_ml_calibration.cc (dense SVD trips AddressSanitizer with
  // the prebuilt libceres); the rank is known from the problem's shape.
  covariance_options.algorithm_type = ceres::SPARSE_QR;
  covariance_options.num_threads = 1;
  ceres::Covariance covariance(covariance_options);
  std::vector<std::pair<const double*, const double*>> pairs;
  for (const auto& block : blocks) pairs.emplace_back(block.first, block.first);
  if (!covariance.Compute(pairs, problem)) {
    return Status::Error(
        "ceres::Covariance could not invert the information: the holds do not determine the "
        "parameters solved for");
  }
  covariances->clear();
  for (const auto& block : blocks) {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> values(block.second,
                                                                                  block.second);
    covariance.GetCovarianceBlock(block.first, block.first, values.data());
    covariances->push_back(values);
  }
  return Status::Ok();
}

// The whitened residuals of every block of `problem`, three per hold, and their sum of squares.
double WhitenedResiduals(ceres::Problem* problem, FerrarisHoldVectors* residuals) {
  std::vector<double> values;
  double cost = 0.0;
  CHECK(problem->Evaluate(ceres::Problem::EvaluateOptions(), &cost, &values, nullptr, nullptr));
  double chi2 = 0.0;
  for (int p = 0; p < kFerrarisHoldCount; ++p) {
    for (int k = 0; k < 3; ++k) {
      const double r = values[3 * p + k];
      if (residuals != nullptr) (*residuals)[p][k] = r;
      chi2 += r * r;
    }
  }
  return chi2;
}

// The unknown-directions problem: a residual per hold, the directions on the sphere, started
// (with `start_directions`) at the specific force `parameters` gives each mean. `parameters`
// and `directions` must outlive `problem`.
void BuildUnknownDirections(const HoldData& holds, double gravity_mps2, bool start_directions,
                            TriadParameters* parameters, FerrarisHoldVectors* directions,
                            ceres::Problem* problem) {
  for (int p = 0; p < kFerrarisHoldCount; ++p) {
    double force[3];
    if (start_directions) {
      TriadSpecificForce(parameters->data(), holds.mean[p].data(), force);
      const double norm =
          std::sqrt(force[0] * force[0] + force[1] * force[1] + force[2] * force[2]);
      for (int k = 0; k < 3; ++k) (*directions)[p][k] = force[k] / norm;
    }
    problem->AddResidualBlock(
        TriadPoseResidual::Create(holds.mean[p], holds.mean_stddev[p], gravity_mps2), nullptr,
        parameters->data(), (*directions)[p].data());
    problem->SetManifold((*directions)[p].data(), new ceres::SphereManifold<3>());
  }
}

Status CheckIdentifiability(const HoldData& holds, double gravity_mps2, const TriadParameters& at,
                            const FerrarisHoldVectors& at_directions,
                            const FerrarisLeastSquaresOptions& options,
                            FerrarisIdentifiability* identifiability) {
  TriadParameters parameters = at;
  FerrarisHoldVectors directions = at_directions;
  ceres::Problem problem;
  BuildUnknownDirections(holds, gravity_mps2, false, &parameters, &directions, &problem);
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.parameter_blocks = {parameters.data()};
  for (auto& direction : directions) evaluate.parameter_blocks.push_back(direction.data());
  ceres::CRSMatrix crs;
  double cost = 0.0;
  if (!problem.Evaluate(evaluate, &cost, nullptr, nullptr, &crs)) {
    return Status::Error("the residuals of the holds could not be evaluated");
  }
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int i = crs.rows[row]; i < crs.rows[row + 1]; ++i)
      jacobian(row, crs.cols[i]) = crs.values[i];
  }
  CHECK_EQ(jacobian.cols(), identifiability->unknowns);
  // Unit columns, so that counts, rad and (m/s^2)/count compare.
  for (int c = 0; c < jacobian.cols(); ++c) {
    const double norm = jacobian.col(c).norm();
    if (norm > 0.0) jacobian.col(c) /= norm;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeFullV);
  const Eigen::VectorXd& singular = svd.singularValues();
  identifiability->singular_values.assign(singular.data(), singular.data() + singular.size());
  identifiability->rank = 0;
  for (int i = 0; i < singular.size(); ++i)
    if (singular[i] > options.rank_tolerance * singular[0]) ++identifiability->rank;
  const int nullity = static_cast<int>(jacobian.cols()) - identifiability->rank;
  const Eigen::MatrixXd null_space = svd.matrixV().rightCols(nullity);
  for (int i = 0; i < kTriadParameterCount; ++i) {
    identifiability->null_space_weight[i] = nullity > 0 ? null_space.row(i).norm() : 0.0;
    const char* name = TriadParameterInfos()[i].name;
    if (identifiability->null_space_weight[i] > options.null_space_weight_limit) {
      identifiability->not_identifiable.push_back(name);
    } else {
      identifiability->identifiable.push_back(name);
    }
  }
  return Status::Ok();
}

// (b): the angles held at `held`, offsets and gains and the directions solved.
Status FitUnknownDirections(const HoldData& holds, double gravity_mps2,
                            const TriadParameters& start, const std::array<double, 3>& held,
                            const QuietSolveOptions& solve, bool with_covariance,
                            TriadParameters* parameters, TriadParameters* stddev,
                            FerrarisHoldVectors* directions, double* chi2, SolverReport* report) {
  *parameters = start;
  (*parameters)[kTriadMisalignmentYz] = held[0];
  (*parameters)[kTriadMisalignmentZy] = held[1];
  (*parameters)[kTriadMisalignmentZx] = held[2];
  ceres::Problem problem;
  BuildUnknownDirections(holds, gravity_mps2, true, parameters, directions, &problem);
  problem.SetManifold(
      parameters->data(),
      new ceres::SubsetManifold(kTriadParameterCount, {kTriadMisalignmentYz, kTriadMisalignmentZy,
                                                       kTriadMisalignmentZx}));
  ACCELCAL_RETURN_IF_ERROR(
      SolveQuietly(solve, &problem, report).WithContext("the fit with unknown directions"));
  *chi2 = WhitenedResiduals(&problem, nullptr);
  if (!with_covariance) return Status::Ok();
  std::vector<Eigen::MatrixXd> covariances;
  ACCELCAL_RETURN_IF_ERROR(
      Covariance(&problem, {{parameters->data(), kTriadParameterCount}}, &covariances)
          .WithContext("the fit with unknown directions"));
  for (int i = 0; i < kTriadParameterCount; ++i)
    (*stddev)[i] = std::sqrt(std::max(0.0, covariances[0](i, i)));
  return Status::Ok();
}

// (a): every hold +-g along an axis of one frame, Q = Q0 Exp(w).
Status FitKnownDirections(const HoldData& holds, double gravity_mps2, const TriadParameters& start,
                          const Eigen::Matrix3d& start_rotation, const QuietSolveOptions& solve,
                          FerrarisKnownDirectionsFit* fit) {
  fit->parameters = start;
  fit->frame_correction_rad = {0.0, 0.0, 0.0};
  ceres::Problem problem;
  for (int p = 0; p < kFerrarisHoldCount; ++p) {
    const Eigen::Vector3d reference = start_rotation.transpose() * HoldAxis(p);
    problem.AddResidualBlock(
        FerrarisHoldResidual::Create(holds.mean[p], holds.mean_stddev[p],
                                     {reference[0], reference[1], reference[2]}, gravity_mps2),
        nullptr, fit->parameters.data(), fit->frame_correction_rad.data());
  }
  ACCELCAL_RETURN_IF_ERROR(SolveQuietly(solve, &problem, &fit->solver)
                               .WithContext("the fit with the holds along the frame's axes"));
  fit->chi2 = WhitenedResiduals(&problem, &fit->whitened_residuals);
  fit->p_value = ChiSquareSurvival(fit->chi2, fit->degrees_of_freedom);
  std::vector<Eigen::MatrixXd> covariances;
  ACCELCAL_RETURN_IF_ERROR(Covariance(&problem,
                                      {{fit->parameters.data(), kTriadParameterCount},
                                       {fit->frame_correction_rad.data(), 3}},
                                      &covariances)
                               .WithContext("the fit with the holds along the frame's axes"));
  for (int i = 0; i < kTriadParameterCount; ++i) {
    for (int j = 0; j < kTriadParameterCount; ++j) fit->covariance[i][j] = covariances[0](i, j);
    fit->stddev[i] = std::sqrt(std::max(0.0, covariances[0](i, i)));
  }
  for (int i = 0; i < 3; ++i)
    fit->frame_correction_stddev_rad[i] = std::sqrt(std::max(0.0, covariances[1](i, i)));
  double correction[9];
  ceres::AngleAxisToRotationMatrix(fit->frame_correction_rad.data(),
                                   ceres::ColumnMajorAdapter3x3(correction));
  fit->frame_rotation = start_rotation * Eigen::Map<const Eigen::Matrix3d>(correction);
  return Status::Ok();
}

}  // namespace

Status FerrarisLeastSquares(const FerrarisSession& session, double gravity_mps2,
                            const TriadParameters& closed_form_triad,
                            const Eigen::Matrix3d& frame_rotation,
                            const FerrarisLeastSquaresOptions& options,
                            FerrarisLeastSquaresResult* result) {
  *result = FerrarisLeastSquaresResult();
  HoldData holds;
  ACCELCAL_RETURN_IF_ERROR(PrepareHolds(session, &holds, &result->noise_variance));

  FerrarisUnknownDirectionsFit& unknown = result->unknown_directions;
  unknown.held_misalignment_rad = {closed_form_triad[kTriadMisalignmentYz],
                                   closed_form_triad[kTriadMisalignmentZy],
                                   closed_form_triad[kTriadMisalignmentZx]};
  ACCELCAL_RETURN_IF_ERROR(FitUnknownDirections(
      holds, gravity_mps2, closed_form_triad, unknown.held_misalignment_rad, options.solve, true,
      &unknown.parameters, &unknown.stddev, &unknown.directions, &unknown.chi2, &unknown.solver));
  // The identifiability of all 21 unknowns where the holds are fitted exactly.
  ACCELCAL_RETURN_IF_ERROR(CheckIdentifiability(holds, gravity_mps2, unknown.parameters,
                                                unknown.directions, options,
                                                &result->identifiability));
  TriadParameters unused_stddev{};
  FerrarisHoldVectors unused_directions{};
  double unused_chi2 = 0.0;
  SolverReport unused_report;
  ACCELCAL_RETURN_IF_ERROR(FitUnknownDirections(holds, gravity_mps2, closed_form_triad,
                                                {0.0, 0.0, 0.0}, options.solve, false,
                                                &unknown.parameters_at_zero_angles, &unused_stddev,
                                                &unused_directions, &unused_chi2, &unused_report));

  return FitKnownDirections(holds, gravity_mps2, closed_form_triad, frame_rotation, options.solve,
                            &result->known_directions);
}

Status AnalyzeFerraris(const FerrarisSession& session, const FerrarisOptions& options,
                       const FerrarisLeastSquaresOptions& least_squares_options,
                       FerrarisAnalysis* analysis) {
  *analysis = FerrarisAnalysis();
  analysis->hold_orthogonality = FerrarisHoldOrthogonality(session);
  ACCELCAL_RETURN_IF_ERROR(FerrarisClosedForm(session, options, &analysis->closed_form));
  ACCELCAL_RETURN_IF_ERROR(ImucalToTriad(analysis->closed_form.accelerometer,
                                         &analysis->closed_form_triad, &analysis->frame_rotation)
                               .WithContext("the closed form in accelcal's convention"));
  return FerrarisLeastSquares(session, options.gravity_mps2, analysis->closed_form_triad,
                              analysis->frame_rotation, least_squares_options,
                              &analysis->least_squares);
}

}  // namespace accelcal
