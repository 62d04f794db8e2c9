#include "estimation/tilt_table/joint_estimator.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>

#include "common/format.h"
#include "estimation/solver/ceres_solve.h"
#include "estimation/solver/identifiability.h"
#include "estimation/tilt_table/joint_data.h"
#include "estimation/tilt_table/trajectory.h"
#include "residuals/calibration_residual.h"
#include "residuals/compressed_calibration_residual.h"
#include "residuals/endpoint_residual.h"

namespace accelcal {
namespace {

std::unique_ptr<ceres::LossFunction> MakeLoss(const JointOptions& options) {
  switch (options.loss) {
    case RobustLoss::kNone:
      return nullptr;
    case RobustLoss::kHuber:
      return std::make_unique<ceres::HuberLoss>(options.loss_scale);
    case RobustLoss::kCauchy:
      return std::make_unique<ceres::CauchyLoss>(options.loss_scale);
  }
  return nullptr;
}

// One solve with the run tied to `landmark` (or to none).
class JointProblem {
 public:
  JointProblem(const JointData& data, const JointOptions& options)
      : data_(data), test_(data.test()), options_(options), loss_(MakeLoss(options)) {}

  // The residual blocks of each group, for chi-square per group.
  struct Groups {
    std::vector<ceres::ResidualBlockId> x;
    std::vector<ceres::ResidualBlockId> y;
    ceres::ResidualBlockId endpoint = nullptr;
  };

  // Adds every residual at `values` (which must outlive `problem`); the parameters not in
  // `free` are held constant. With `compress`, each axis's tilt-test residuals become one
  // CompressedCalibrationResidual (the same cost and J^T J at any parameters, evaluated
  // in time independent of the sample count); without it (robust losses act per sample,
  // and Linearize wants one row per sample) each sample is its own block.
  Status Build(const Landmark* landmark, const std::vector<Parameter>& free,
               ModelParameters<double>* values, ceres::Problem* problem, Groups* groups,
               bool compress) {
    // The residuals' parameter blocks are the catalogue's values, in each residual's order.
    auto blocks = [&](const auto& parameters) {
      std::vector<double*> pointers;
      for (const Parameter parameter : parameters) pointers.push_back(&(*values)[parameter]);
      return pointers;
    };
    const int n = test_.size();
    const AxisNoise noise[2] = {options_.Noise(0), options_.Noise(1)};
    std::unique_ptr<CompressedCalibrationResidual> compressed[2];
    if (compress && loss_ == nullptr) {
      // A model outside the compressed basis falls back to the per-sample residuals. The
      // Gram matrices are taken about the baseline, where every solve starts.
      if (!data_.CompressedResiduals(options_, compressed).ok()) {
        compressed[0].reset();
        compressed[1].reset();
      }
    }
    const bool per_sample = compressed[0] == nullptr;
    if (!per_sample) {
      for (int a = 0; a < 2; ++a) {
        const std::vector<double*> parameters = blocks(compressed[a]->blocks());
        (a == 0 ? groups->x : groups->y)
            .push_back(problem->AddResidualBlock(
                CompressedCalibrationResidual::Create(compressed[a].release()), nullptr,
                parameters));
      }
    }
    const std::vector<double*> blocks_x = blocks(CalibrationResidual::Blocks(SensingAxis::kX));
    const std::vector<double*> blocks_y = blocks(CalibrationResidual::Blocks(SensingAxis::kY));
    const std::vector<AxisNoise::Whitening> whitening[2] = {
        per_sample ? noise[0].WhiteningOf(n) : std::vector<AxisNoise::Whitening>(),
        per_sample ? noise[1].WhiteningOf(n) : std::vector<AxisNoise::Whitening>()};
    for (int i = 0; per_sample && i < n; ++i) {
      const double u = DriftCoordinate(i, n);
      const double u_previous = i > 0 ? DriftCoordinate(i - 1, n) : 0.0;
      for (int a = 0; a < 2; ++a) {
        const std::vector<double>& measured = a == 0 ? test_.measured_x : test_.measured_y;
        const CalibrationResidual::Sample sample = {test_.theta_rad[i], measured[i], u};
        const CalibrationResidual::Sample previous =
            i > 0 ? CalibrationResidual::Sample{test_.theta_rad[i - 1], measured[i - 1], u_previous}
                  : CalibrationResidual::Sample();
        // An outlier's block stays (with zero weight), so rows keep their sample's place.
        (a == 0 ? groups->x : groups->y)
            .push_back(problem->AddResidualBlock(
                CalibrationResidual::CreateWhitened(
                    sample, previous, a == 0 ? SensingAxis::kX : SensingAxis::kY,
                    options_.gravity_mps2, whitening[a][i].current, whitening[a][i].previous),
                loss_.get(), a == 0 ? blocks_x : blocks_y));
      }
    }
    if (landmark != nullptr) {
      // The endpoint's noise covariance at the starting point (the baseline): the
      // whitening must not move with the parameters, or the cost would not be a chi-square.
      const DeadReckoningResult* baseline_trajectory = nullptr;
      ACCELCAL_RETURN_IF_ERROR(data_.BaselineTrajectory(options_, &baseline_trajectory));
      const VehicleRun& run = data_.run();
      const RunConditions& conditions = data_.conditions();
      auto* functor = new EndpointResidual(
          run.measured_x, run.measured_y, run.SampleInterval(),
          Eigen::Vector2d(conditions.initial_position_x_m, conditions.initial_position_y_m),
          Eigen::Vector2d(conditions.initial_velocity_x_mps, conditions.initial_velocity_y_mps),
          Eigen::Vector2d(landmark->x_m, landmark->y_m), baseline_trajectory->noise_part,
          options_.landmark_sigma_m,
          /*linear_inverse=*/EndpointResidual::InverseIsAffine(*values, free));
      groups->endpoint = problem->AddResidualBlock(EndpointResidual::Create(functor), nullptr,
                                                   blocks(EndpointResidual::kBlocks));
    }
    for (const ParameterInfo& info : ParameterCatalogue()) {
      if (IsNoiseRatio(info.parameter)) continue;
      double* pointer = &(*values)[info.parameter];
      if (!problem->HasParameterBlock(pointer)) continue;
      if (std::find(free.begin(), free.end(), info.parameter) == free.end()) {
        problem->SetParameterBlockConstant(pointer);
      }
    }
    return Status::Ok();
  }

  Status Solve(const Landmark* landmark, JointResult* result) {
    ParameterEstimate& estimate = result->estimate;
    estimate = ParameterEstimate();
    ModelParameters<double>& values = estimate.values;
    // Start from the closed-form baseline; every effect from its neutral value.
    const BaselineFit* start = nullptr;
    ACCELCAL_RETURN_IF_ERROR(data_.Baseline(options_, &start));
    const ParameterEstimate baseline = FromBaselineFit(*start);
    for (const Parameter parameter : baseline.free) {
      values[parameter] = baseline.Value(parameter);
    }
    const RunConditions& conditions = data_.conditions();
    values[Parameter::kNoiseVarianceX] = options_.noise_variance_x / conditions.noise_variance_x;
    values[Parameter::kNoiseVarianceY] = options_.noise_variance_y / conditions.noise_variance_y;
    estimate.noise_correlation = options_.noise_correlation;
    estimate.free = baseline.free;
    for (const Parameter effect : options_.effects) estimate.free.push_back(effect);

    ceres::Problem::Options problem_options;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    Groups groups;
    ACCELCAL_RETURN_IF_ERROR(
        Build(landmark, estimate.free, &values, &problem, &groups, options_.compress_calibration));
    if (landmark != nullptr) result->landmark = landmark->name;
    auto block = [&](Parameter parameter) { return &values[parameter]; };

    std::vector<double*> free_blocks;
    for (const Parameter parameter : estimate.free) free_blocks.push_back(block(parameter));
    // Checked at the start, because an unidentifiable direction lets the solver wander
    // until the residuals overflow, and again at the optimum, where the covariance is taken.
    ACCELCAL_RETURN_IF_ERROR(CheckIdentifiable(&problem, free_blocks, estimate.free));
    QuietSolveOptions solve;
    solve.max_iterations = options_.max_iterations;
    solve.num_threads = options_.num_threads;
    ACCELCAL_RETURN_IF_ERROR(SolveQuietly(solve, &problem, &result->solver));
    ACCELCAL_RETURN_IF_ERROR(CheckIdentifiable(&problem, free_blocks, estimate.free));

    ceres::Covariance::Options covariance_options;
    covariance_options.algorithm_type = ceres::DENSE_SVD;
    covariance_options.num_threads = options_.num_threads;
    ceres::Covariance covariance(covariance_options);
    std::vector<const double*> const_blocks(free_blocks.begin(), free_blocks.end());
    if (!covariance.Compute(const_blocks, &problem)) {
      return Status::Error("ceres::Covariance could not invert the information matrix");
    }
    estimate.covariance.resize(free_blocks.size(), free_blocks.size());
    covariance.GetCovarianceMatrix(const_blocks, estimate.covariance.data());

    auto chi_square = [&](const std::vector<ceres::ResidualBlockId>& blocks) {
      ceres::Problem::EvaluateOptions evaluate_options;
      evaluate_options.residual_blocks = blocks;
      evaluate_options.apply_loss_function = false;
      double cost = 0.0;
      problem.Evaluate(evaluate_options, &cost, nullptr, nullptr, nullptr);
      return 2.0 * cost;
    };
    result->chi2_x = chi_square(groups.x);
    result->chi2_y = chi_square(groups.y);
    result->chi2_endpoint = groups.endpoint != nullptr ? chi_square({groups.endpoint}) : 0.0;
    result->samples = test_.size();
    return Status::Ok();
  }

  // The whitened residuals and their Jacobian with respect to `columns` at `values`
  // (rows in the order the residuals were added: x_0, y_0, x_1, y_1, ..., then the endpoint).
  Status Linearize(const Landmark* landmark, const ModelParameters<double>& at,
                   const std::vector<Parameter>& columns, Eigen::MatrixXd* jacobian,
                   Eigen::VectorXd* residual) {
    ModelParameters<double> values = at;
    ceres::Problem::Options problem_options;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    Groups groups;
    ACCELCAL_RETURN_IF_ERROR(
        Build(landmark, columns, &values, &problem, &groups, /*compress=*/false));
    std::vector<double*> blocks;
    for (const Parameter parameter : columns) blocks.push_back(&values[parameter]);
    ceres::Problem::EvaluateOptions evaluate_options;
    evaluate_options.parameter_blocks = blocks;
    evaluate_options.apply_loss_function = false;
    std::vector<double> residuals;
    ceres::CRSMatrix crs;
    problem.Evaluate(evaluate_options, nullptr, &residuals, nullptr, &crs);
    *jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
    for (int row = 0; row < crs.num_rows; ++row) {
      for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k)
        (*jacobian)(row, crs.cols[k]) = crs.values[k];
    }
    *residual = Eigen::Map<const Eigen::VectorXd>(residuals.data(), residuals.size());
    return Status::Ok();
  }

 private:
  // The information matrix J^T J of the free parameters at the problem's current values,
  // checked for directions the data do not constrain (estimation/solver/identifiability.h).
  Status CheckIdentifiable(ceres::Problem* problem, const std::vector<double*>& blocks,
                           const std::vector<Parameter>& names) {
    ceres::Problem::EvaluateOptions evaluate_options;
    evaluate_options.parameter_blocks = blocks;
    ceres::CRSMatrix jacobian;
    problem->Evaluate(evaluate_options, nullptr, nullptr, nullptr, &jacobian);
    const int p = static_cast<int>(blocks.size());
    Eigen::MatrixXd information = Eigen::MatrixXd::Zero(p, p);
    for (int row = 0; row < jacobian.num_rows; ++row) {
      for (int a = jacobian.rows[row]; a < jacobian.rows[row + 1]; ++a) {
        for (int b = jacobian.rows[row]; b < jacobian.rows[row + 1]; ++b) {
          information(jacobian.cols[a], jacobian.cols[b]) +=
              jacobian.values[a] * jacobian.values[b];
        }
      }
    }
    return accelcal::CheckIdentifiable(information, names, options_.identifiability_threshold);
  }

  const JointData& data_;
  const CalibrationTest& test_;
  const JointOptions& options_;
  std::unique_ptr<ceres::LossFunction> loss_;
};

// How many sigma each landmark is from the baseline's dead-reckoned endpoint, with the
// endpoint covariance (parameters and run noise) plus the landmarks' own uncertainty.
std::vector<double> BaselineLandmarkSigmas(const DeadReckoningResult& baseline,
                                           const std::vector<Landmark>& landmarks,
                                           double landmark_sigma_m) {
  const Eigen::Matrix2d covariance =
      baseline.covariance + landmark_sigma_m * landmark_sigma_m * Eigen::Matrix2d::Identity();
  const Eigen::LDLT<Eigen::Matrix2d> factor(covariance);
  std::vector<double> sigmas;
  for (const Landmark& landmark : landmarks) {
    const Eigen::Vector2d offset = Eigen::Vector2d(landmark.x_m, landmark.y_m) - baseline.endpoint;
    sigmas.push_back(std::sqrt(std::max(0.0, offset.dot(factor.solve(offset)))));
  }
  return sigmas;
}

}  // namespace

const char* RobustLossName(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::kNone:
      return "none";
    case RobustLoss::kHuber:
      return "huber";
    case RobustLoss::kCauchy:
      return "cauchy";
  }
  return "none";
}

Status ParseRobustLoss(const std::string& name, RobustLoss* loss) {
  for (const RobustLoss candidate : {RobustLoss::kNone, RobustLoss::kHuber, RobustLoss::kCauchy}) {
    if (name == RobustLossName(candidate)) {
      *loss = candidate;
      return Status::Ok();
    }
  }
  return Status::Error("--loss must be none, huber or cauchy, got '" + name + "'");
}

Status LinearizeJoint(const JointData& data, const JointOptions& options, const JointResult& at,
                      Eigen::MatrixXd* jacobian, Eigen::VectorXd* residual,
                      const std::vector<Parameter>* columns) {
  JointProblem problem(data, options);
  return problem.Linearize(data.FindLandmark(at.landmark), at.estimate.values,
                           columns != nullptr ? *columns : at.estimate.free, jacobian, residual);
}

Status SolveJoint(const CalibrationTest& test, const VehicleRun& run,
                  const RunConditions& conditions, const std::vector<Landmark>& landmarks,
                  const JointOptions& options, JointResult* result) {
  const JointData data(test, run, conditions, landmarks);
  return SolveJoint(data, options, result);
}

Status SolveJoint(const JointData& data, const JointOptions& options, JointResult* result) {
  *result = JointResult();
  const std::vector<Landmark>& landmarks = data.landmarks();
  for (const Parameter effect : options.effects) {
    if (IsNoiseRatio(effect) || Info(effect).baseline) {
      return Status::Error(std::string(Info(effect).name) + " cannot be a joint effect");
    }
    if (ActsOnlyInRun(effect) && options.landmark_mode == JointOptions::Landmark::kNone) {
      return Status::Error(std::string("not identifiable: ") + Info(effect).name +
                           " is observable only through the run's endpoint; tie the run to a "
                           "landmark (--landmark=NAME or --landmark=auto)");
    }
  }
  const BaselineFit* start = nullptr;
  ACCELCAL_RETURN_IF_ERROR(data.Baseline(options, &start));
  JointProblem problem(data, options);
  if (options.landmark_mode == JointOptions::Landmark::kNone) return problem.Solve(nullptr, result);
  const DeadReckoningResult* baseline = nullptr;
  ACCELCAL_RETURN_IF_ERROR(data.BaselineTrajectory(options, &baseline));
  const std::vector<double> sigmas =
      BaselineLandmarkSigmas(*baseline, landmarks, options.landmark_sigma_m);
  const Eigen::Vector2d& endpoint = baseline->endpoint;
  auto implausible = [&](size_t k) {
    return StringPrintf(
        "landmark %s at (%.6g, %.6g) m is %.3g sigma from the dead-reckoned endpoint (%.6g, "
        "%.6g) m, beyond what any sensor error of the model can explain (%.0f sigma); check its "
        "coordinates (m)",
        landmarks[k].name.c_str(), landmarks[k].x_m, landmarks[k].y_m, sigmas[k], endpoint.x(),
        endpoint.y(), options.implausible_landmark_sigma);
  };
  if (options.landmark_mode == JointOptions::Landmark::kNamed) {
    if (const Landmark* landmark = data.FindLandmark(options.landmark_name)) {
      const size_t k = static_cast<size_t>(landmark - landmarks.data());
      if (!(sigmas[k] <= options.implausible_landmark_sigma)) {
        return Status::Error(implausible(k) + " or choose another with --landmark");
      }
      return problem.Solve(landmark, result);
    }
    std::string names;
    for (const Landmark& landmark : landmarks) names += (names.empty() ? "" : ", ") + landmark.name;
    return Status::Error("--landmark=" + options.landmark_name + " is not one of the landmarks (" +
                         names + ")");
  }
  // One solve per landmark; the hypotheses share every residual and its whitening, so
  // their costs compare directly: posterior_k = exp(-cost_k) / sum_i exp(-cost_i).
  if (landmarks.empty()) return Status::Error("--landmark=auto needs landmarks");
  std::vector<JointResult> solutions(landmarks.size());
  double best_cost = HUGE_VAL;
  size_t best = landmarks.size();
  for (size_t k = 0; k < landmarks.size(); ++k) {
    if (!(sigmas[k] <= options.implausible_landmark_sigma)) continue;
    ACCELCAL_RETURN_IF_ERROR(
        problem.Solve(&landmarks[k], &solutions[k]).WithContext("landmark " + landmarks[k].name));
    const double cost =
        0.5 * (solutions[k].chi2_x + solutions[k].chi2_y + solutions[k].chi2_endpoint);
    if (cost < best_cost) {
      best_cost = cost;
      best = k;
    }
  }
  if (best == landmarks.size()) {
    size_t nearest = 0;
    for (size_t k = 1; k < landmarks.size(); ++k) {
      if (sigmas[k] < sigmas[nearest]) nearest = k;
    }
    return Status::Error("no landmark is plausible: the nearest, " + implausible(nearest));
  }
  std::vector<LandmarkHypothesis> hypotheses;
  double sum = 0.0;
  for (size_t k = 0; k < landmarks.size(); ++k) {
    LandmarkHypothesis hypothesis;
    hypothesis.name = landmarks[k].name;
    hypothesis.baseline_sigma = sigmas[k];
    hypothesis.solved = sigmas[k] <= options.implausible_landmark_sigma;
    if (hypothesis.solved) {
      hypothesis.cost =
          0.5 * (solutions[k].chi2_x + solutions[k].chi2_y + solutions[k].chi2_endpoint);
      hypothesis.chi2_endpoint = solutions[k].chi2_endpoint;
      hypothesis.posterior = std::exp(-(hypothesis.cost - best_cost));
    }
    sum += hypothesis.posterior;
    hypotheses.push_back(hypothesis);
  }
  for (LandmarkHypothesis& hypothesis : hypotheses) hypothesis.posterior /= sum;
  *result = solutions[best];
  result->hypotheses = hypotheses;
  return Status::Ok();
}

}  // namespace accelcal
