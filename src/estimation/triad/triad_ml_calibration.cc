#include "estimation/triad/triad_ml_calibration.h"

#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>

#include "common/format.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/triad/triad_identifiability.h"
#include "residuals/triad_pose_residual.h"

namespace accelcal {
namespace {

// At least one degree of freedom.
int MinPoses(int parameter_count) { return parameter_count + 1; }

// The names of the estimated parameters in the order of the Jacobian's columns: the 9 triad
// parameters, then the estimated effect coefficients.
std::vector<std::string> EstimatedParameterNames(const std::vector<int>& effects) {
  std::vector<std::string> names;
  for (const TriadParameterInfo& info : TriadParameterInfos()) names.push_back(info.name);
  const std::vector<TriadEffectCoefficient> coefficients = TriadEffectCoefficientList();
  for (int c : effects) names.push_back(coefficients[c].name);
  return names;
}

// s_k^2 pooled over the poses, weighted by their N_p - 1 degrees of freedom.
Status PooledNoiseVariance(const std::vector<TriadPoseMean>& poses, std::array<double, 3>* pooled) {
  for (const TriadPoseMean& pose : poses) {
    if (pose.sample_count < 2) {
      return Status::Error(StringPrintf(
          "a pose of %d sample(s) has no sample variance; every pose needs at least 2 samples",
          pose.sample_count));
    }
  }
  *pooled = PooledWithinPoseVariance(poses);
  for (int k = 0; k < 3; ++k) {
    if (!((*pooled)[k] > 0.0) || !std::isfinite((*pooled)[k])) {
      return Status::Error(StringPrintf(
          "the output of axis %c does not vary within any pose (pooled variance %g): its noise "
          "is below the output's resolution (each pose sits on one level; steps of one level "
          "dominate the noise), so the noise that weights the residuals cannot be measured from "
          "the log; record at a finer resolution (a smaller range or more bits)",
          "xyz"[k], (*pooled)[k]));
    }
  }
  return Status::Ok();
}

// When the directions lie near a plane: its normal, to say how the sensor was turned.
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
      "; all poses' gravity directions lie within a few degrees of a plane (normal (%.3f, %.3f, "
      "%.3f), sensor frame: the sensor was only turned about it); add poses with gravity along "
      "or near it",
      normal[0], normal[1], normal[2]);
}

// What the poses tell about the estimated parameters, and which poses would tell more.
// Everything is evaluated at one point of parameter space (the refusal's).
class PoseAdvisor {
 public:
  // `effects` may be null (no effect estimated); `estimated` lists its coefficients that are.
  PoseAdvisor(const double* parameters, const double* effects, const std::vector<int>& estimated,
              const std::array<double, 3>& mean_stddev, double gravity_mps2)
      : parameters_(parameters),
        effects_(effects),
        estimated_(estimated),
        mean_stddev_(mean_stddev),
        gravity_mps2_(gravity_mps2),
        parameter_count_(kTriadParameterCount + static_cast<int>(estimated.size())) {}

  // a_p: the pose's information on the parameters is a_p a_p^T, its own direction
  // marginalised. The pose's 3 residuals move with the parameters through J (3 x parameters)
  // and with its direction through B (3 x 2, the sphere's tangent plane); only the residual
  // direction q orthogonal to both columns of B carries information on the parameters.
  Eigen::VectorXd InformationVector(const std::array<double, 3>& direction) const {
    // A pose at the time origin: a drift term's information depends on when the pose is
    // held, which advice on directions cannot choose.
    const std::unique_ptr<ceres::CostFunction> cost(
        effects_ == nullptr
            ? TriadPoseResidual::Create({0.0, 0.0, 0.0}, mean_stddev_, gravity_mps2_)
            : TriadPoseResidual::CreateWithEffects({0.0, 0.0, 0.0}, mean_stddev_, gravity_mps2_,
                                                   TriadPoseContext()));
    double residual[3];
    Eigen::Matrix<double, 3, kTriadParameterCount, Eigen::RowMajor> jacobian_parameters;
    Eigen::Matrix<double, 3, kTriadEffectCoefficientCount, Eigen::RowMajor> jacobian_effects;
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> jacobian_direction;
    std::vector<const double*> blocks = {parameters_};
    std::vector<double*> jacobians = {jacobian_parameters.data()};
    if (effects_ != nullptr) {
      blocks.push_back(effects_);
      jacobians.push_back(jacobian_effects.data());
    }
    blocks.push_back(direction.data());
    jacobians.push_back(jacobian_direction.data());
    CHECK(cost->Evaluate(blocks.data(), residual, jacobians.data()));

    const Eigen::Vector3d n(direction[0], direction[1], direction[2]);
    const Eigen::Vector3d helper =
        std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d tangent_1 = n.cross(helper).normalized();
    const Eigen::Vector3d tangent_2 = n.cross(tangent_1);
    const Eigen::Vector3d q =
        (jacobian_direction * tangent_1).cross(jacobian_direction * tangent_2).normalized();
    Eigen::VectorXd a(parameter_count_);
    a.head<kTriadParameterCount>() = jacobian_parameters.transpose() * q;
    for (size_t i = 0; i < estimated_.size(); ++i)
      a[kTriadParameterCount + i] = jacobian_effects.col(estimated_[i]).dot(q);
    return a;
  }

  // The poses to add to `held` (unit directions), best first, as the header states.
  std::vector<std::array<double, 3>> Suggest(const std::vector<std::array<double, 3>>& held) const {
    const std::vector<std::array<double, 3>> candidates = CandidateDirections();
    std::vector<Eigen::VectorXd> candidate_vectors;
    Eigen::VectorXd sphere_diagonal = Eigen::VectorXd::Zero(parameter_count_);
    Eigen::MatrixXd sphere = Eigen::MatrixXd::Zero(parameter_count_, parameter_count_);
    for (const auto& direction : candidates) {
      candidate_vectors.push_back(InformationVector(direction));
      sphere += candidate_vectors.back() * candidate_vectors.back().transpose();
    }
    sphere /= static_cast<double>(candidates.size());
    // Per-parameter scale: the information one sphere-spread pose gives it.
    const Eigen::VectorXd scale = sphere.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const double enough =
        SmallestEigenvalue(scale.asDiagonal() * sphere * scale.asDiagonal());  // one pose's
    for (Eigen::VectorXd& a : candidate_vectors) a = scale.cwiseProduct(a);

    Eigen::MatrixXd information = Eigen::MatrixXd::Zero(parameter_count_, parameter_count_);
    for (const auto& direction : held) {
      const Eigen::VectorXd a = scale.cwiseProduct(InformationVector(direction));
      information += a * a.transpose();
    }
    const int min_poses = MinPoses(parameter_count_);
    std::vector<std::array<double, 3>> suggested;
    while (suggested.size() < 12 &&
           (SmallestEigenvalue(information) < enough ||
            static_cast<int>(held.size() + suggested.size()) < min_poses)) {
      const double before = Objective(information);
      std::vector<double> gains(candidates.size());
      size_t best = 0;
      for (size_t c = 0; c < candidates.size(); ++c) {
        gains[c] =
            Objective(information + candidate_vectors[c] * candidate_vectors[c].transpose()) -
            before;
        if (gains[c] > gains[best]) best = c;
      }
      // A direction a person can hold (an axis, an edge or a corner of a box up) when it
      // does nearly as well.
      for (size_t c = 0; c < kBoxDirections; ++c) {
        if (gains[c] >= 0.95 * gains[best] && (best >= kBoxDirections || gains[c] > gains[best]))
          best = c;
      }
      information += candidate_vectors[best] * candidate_vectors[best].transpose();
      suggested.push_back(candidates[best]);
    }
    return suggested;
  }

 private:
  static constexpr size_t kBoxDirections = 26;

  // The 26 directions of a box's faces, edges and corners first, then a Fibonacci lattice
  // of 600 points over the sphere.
  static std::vector<std::array<double, 3>> CandidateDirections() {
    std::vector<std::array<double, 3>> directions;
    for (int x = -1; x <= 1; ++x) {
      for (int y = -1; y <= 1; ++y) {
        for (int z = -1; z <= 1; ++z) {
          if (x == 0 && y == 0 && z == 0) continue;
          const double norm = std::sqrt(static_cast<double>(x * x + y * y + z * z));
          directions.push_back({x / norm, y / norm, z / norm});
        }
      }
    }
    // Axes before edges before corners, so that a tie keeps the simplest.
    std::stable_sort(directions.begin(), directions.end(), [](const auto& a, const auto& b) {
      auto zeros = [](const std::array<double, 3>& d) {
        return (d[0] == 0.0) + (d[1] == 0.0) + (d[2] == 0.0);
      };
      return zeros(a) > zeros(b);
    });
    constexpr int kLattice = 600;
    const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < kLattice; ++i) {
      const double z = 1.0 - (2.0 * i + 1.0) / kLattice;
      const double r = std::sqrt(1.0 - z * z);
      directions.push_back({r * std::cos(golden_angle * i), r * std::sin(golden_angle * i), z});
    }
    return directions;
  }

  static double SmallestEigenvalue(const Eigen::MatrixXd& information) {
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(information, Eigen::EigenvaluesOnly)
        .eigenvalues()[0];
  }

  // sum_i log(lambda_i + 1e-3): raising a null eigenvalue to one pose's worth gains ~7, so
  // the directions the poses lack come first, all of them, not only the weakest one.
  static double Objective(const Eigen::MatrixXd& information) {
    const Eigen::VectorXd eigenvalues =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(information, Eigen::EigenvaluesOnly)
            .eigenvalues();
    double sum = 0.0;
    for (int i = 0; i < eigenvalues.size(); ++i)
      sum += std::log(std::max(eigenvalues[i], 0.0) + 1e-3);
    return sum;
  }

  const double* parameters_;
  const double* effects_;
  const std::vector<int> estimated_;
  const std::array<double, 3> mean_stddev_;
  const double gravity_mps2_;
  const int parameter_count_;
};

// "x up", "-y up" ... for an axis, else the vector that points up.
std::string DescribeDirection(const std::array<double, 3>& d) {
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) > 0.999) return StringPrintf("%c %s", "xyz"[k], d[k] > 0 ? "up" : "down");
  }
  return StringPrintf("(%.2f, %.2f, %.2f) up", d[0], d[1], d[2]);
}

// The poses to add, in words: after the plane's advice (`after_planar_hint`) as its example.
// At most 6 are listed; the result holds them all.
std::string SuggestionText(const std::vector<std::array<double, 3>>& suggested,
                           bool after_planar_hint) {
  if (suggested.empty()) return "";
  constexpr size_t kListed = 6;
  std::string list;
  for (size_t i = 0; i < std::min(suggested.size(), kListed); ++i)
    list += (i == 0 ? "" : ", ") + DescribeDirection(suggested[i]);
  if (suggested.size() > kListed) list += StringPrintf(" and %zu more", suggested.size() - kListed);
  const std::string poses =
      suggested.size() == 1 ? "this pose" : StringPrintf("these %zu poses", suggested.size());
  return (after_planar_hint ? ", e.g. " : "; add ") + poses + " held with " + list +
         " (sensor frame)";
}

// What CheckIdentifiable needs of the problem being solved.
struct ProblemState {
  const TriadMlOptions* options;
  std::vector<std::string> parameter_names;  // 9 + the estimated effect coefficients
  std::vector<int> effects_estimated;
  double* parameters;           // the 9 triad parameters
  double* effects;              // the effects' block, or null when none is estimated
  std::vector<double*> blocks;  // the parameter blocks, triad ones first
  std::vector<ceres::ResidualBlockId> residual_blocks;
  std::array<double, 3> mean_stddev;  // of a pose of the median sample count (counts)
};

std::vector<std::array<double, 3>> SuggestedPoses(const ProblemState& state,
                                                  const std::vector<std::array<double, 3>>& held) {
  if (!state.options->suggest_poses) return {};
  return PoseAdvisor(state.parameters, state.effects, state.effects_estimated, state.mean_stddev,
                     state.options->gravity_mps2)
      .Suggest(held);
}

// Evaluates the whitened residuals and their Jacobian (in the directions' tangent space) and
// refuses, naming the parameters and the poses to add, when the sensor parameters' reduced
// information (triad_identifiability.h: the directions eliminated pose by pose) is
// rank-deficient. `reduced`, when given, receives that information.
Status CheckIdentifiable(const ProblemState& state,
                         const std::vector<std::array<double, 3>>& directions,
                         ceres::Problem* problem, std::vector<double>* residuals,
                         TriadReducedInformation* reduced, TriadMlResult* result) {
  const int pose_count = static_cast<int>(directions.size());
  ceres::Problem::EvaluateOptions evaluate_options;
  evaluate_options.parameter_blocks = state.blocks;
  evaluate_options.residual_blocks = state.residual_blocks;
  double cost = 0.0;
  std::vector<double> values;
  ceres::CRSMatrix crs;
  if (!problem->Evaluate(evaluate_options, &cost, &values, nullptr, &crs)) {
    return Status::Error("the residuals could not be evaluated at the parameters reached");
  }
  const int parameter_count = static_cast<int>(state.parameter_names.size());
  CHECK_EQ(crs.num_cols, parameter_count + 2 * pose_count);
  if (residuals != nullptr) *residuals = values;
  TriadArrowJacobian jacobian;
  CHECK(TriadArrowJacobianFromCrs(crs, parameter_count, &jacobian))
      << "a pose's residuals depend on another pose's direction";
  TriadReducedInformation information = ReducedInformation(jacobian);
  const std::vector<std::string> unidentifiable = UnidentifiableParametersReduced(
      jacobian, information, state.parameter_names, state.options->rank_tolerance);
  if (reduced != nullptr) *reduced = std::move(information);
  if (unidentifiable.empty()) return Status::Ok();
  result->unidentifiable = unidentifiable;
  result->suggested_directions = SuggestedPoses(state, directions);
  const std::string names = JoinStrings(unidentifiable);
  const std::string planar_hint = PlanarHint(directions);
  return Status::Error(StringPrintf(
      "the %d poses cannot determine the triad: %s not identifiable (the Jacobian of the "
      "%d residuals in the %d unknowns is rank-deficient)%s%s",
      pose_count, (names + (unidentifiable.size() == 1 ? " is" : " are")).c_str(), 3 * pose_count,
      parameter_count + 2 * pose_count, planar_hint.c_str(),
      SuggestionText(result->suggested_directions, !planar_hint.empty()).c_str()));
}

// The standard deviation of the mean of a pose of the median sample count.
std::array<double, 3> TypicalMeanStddev(const std::vector<TriadPoseMean>& poses,
                                        const std::array<double, 3>& noise_variance) {
  std::vector<int> counts;
  for (const TriadPoseMean& pose : poses) counts.push_back(pose.sample_count);
  std::nth_element(counts.begin(), counts.begin() + counts.size() / 2, counts.end());
  const double median = counts[counts.size() / 2];
  return {std::sqrt(noise_variance[0] / median), std::sqrt(noise_variance[1] / median),
          std::sqrt(noise_variance[2] / median)};
}

}  // namespace

std::vector<int> TriadEstimatedEffects(const TriadMlOptions& options) {
  std::vector<int> effects = options.effects;
  if (options.scale_nonlinearity) {
    const int first = TriadEffectCoefficientIndex("scale_nonlinearity_x");
    for (int k = 0; k < kTriadScaleNonlinearityCount; ++k) effects.push_back(first + k);
  }
  std::sort(effects.begin(), effects.end());
  effects.erase(std::unique(effects.begin(), effects.end()), effects.end());
  return effects;
}

int TriadEstimatedParameterCount(const TriadMlOptions& options) {
  return kTriadParameterCount + static_cast<int>(TriadEstimatedEffects(options).size());
}

std::array<double, 3> PooledWithinPoseVariance(const std::vector<TriadPoseMean>& poses) {
  std::array<double, 3> sum{};
  double weight = 0.0;
  for (const TriadPoseMean& pose : poses) {
    for (int k = 0; k < 3; ++k) sum[k] += (pose.sample_count - 1) * pose.variance[k];
    weight += pose.sample_count - 1;
  }
  for (double& value : sum) value /= weight;
  return sum;
}

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
    pose.time_s = 0.5 * (interval.start_s + interval.end_s);
    pose.duration_s = interval.end_s - interval.start_s;
    poses.push_back(pose);
  }
  return poses;
}

Status CalibrateTriadMl(const std::vector<TriadPoseMean>& poses, const TriadMlOptions& options,
                        TriadMlResult* result) {
  *result = TriadMlResult();
  const int pose_count = static_cast<int>(poses.size());
  const std::vector<int> estimated = TriadEstimatedEffects(options);
  const int parameter_count = kTriadParameterCount + static_cast<int>(estimated.size());
  result->pose_count = pose_count;
  result->effects_estimated = estimated;
  if (pose_count < 1) return Status::Error("no static poses to calibrate from");
  ACCELCAL_RETURN_IF_ERROR(PooledNoiseVariance(poses, &result->noise_variance));
  if (!options.pose_mean_variance.empty() &&
      static_cast<int>(options.pose_mean_variance.size()) != pose_count) {
    return Status::Error(StringPrintf("%zu pose-mean variances for %d poses",
                                      options.pose_mean_variance.size(), pose_count));
  }
  for (const int c : estimated) {
    if (c < 0 || c >= kTriadEffectCoefficientCount)
      return Status::Error(StringPrintf("no triad effect coefficient %d", c));
  }
  result->time_origin_s = 0.0;
  for (const TriadPoseMean& pose : poses) result->time_origin_s += pose.time_s / pose_count;

  // Initial directions: the initial calibration's specific force of each mean, normalised
  // (the 9 parameters and the second-order terms, the effects that change a pose's direction
  // little).
  result->parameters = options.initial;
  result->effects = options.initial_effects;
  for (int c = 0; c < kTriadEffectCoefficientCount; ++c) {
    if (!std::binary_search(estimated.begin(), estimated.end(), c)) result->effects[c] = 0.0;
  }
  const int first_k2 = TriadEffectCoefficientIndex("scale_nonlinearity_x");
  double* effects = estimated.empty() ? nullptr : result->effects.data();
  result->directions.resize(pose_count);
  for (int p = 0; p < pose_count; ++p) {
    double force[3] = {0.0, 0.0, 0.0};
    const bool mapped = TriadSpecificForce(options.initial.data(), &result->effects[first_k2],
                                           poses[p].mean.data(), force);
    const double norm = std::sqrt(force[0] * force[0] + force[1] * force[1] + force[2] * force[2]);
    if (!mapped || !(norm > 0.0) || !std::isfinite(norm)) {
      return Status::Error(StringPrintf(
          "pose %d: the initial calibration maps its mean to a specific force of norm %g; give "
          "an initial bias near the output at zero specific force",
          p + 1, mapped ? norm : NAN));
    }
    for (int k = 0; k < 3; ++k) result->directions[p][k] = force[k] / norm;
  }

  ceres::Problem problem;
  ProblemState state;
  state.options = &options;
  state.parameter_names = EstimatedParameterNames(estimated);
  state.effects_estimated = estimated;
  state.parameters = result->parameters.data();
  state.effects = effects;
  state.blocks = {result->parameters.data()};
  if (effects != nullptr) state.blocks.push_back(effects);
  state.mean_stddev = TypicalMeanStddev(poses, result->noise_variance);
  result->mean_stddev.resize(pose_count);
  result->mean_stddev_from_caller = !options.pose_mean_variance.empty();
  for (int p = 0; p < pose_count; ++p) {
    std::array<double, 3>& mean_stddev = result->mean_stddev[p];
    for (int k = 0; k < 3; ++k) {
      const double variance =
          (options.pose_mean_variance.empty() ? result->noise_variance[k] / poses[p].sample_count
                                              : options.pose_mean_variance[p][k]) +
          options.quantisation_variance[k];
      if (!(variance > 0.0) || !std::isfinite(variance)) {
        return Status::Error(StringPrintf(
            "pose %d: the variance of its mean on axis %c is %g; the noise model must give a "
            "positive variance",
            p + 1, "xyz"[k], variance));
      }
      mean_stddev[k] = std::sqrt(variance);
    }
    double* direction = result->directions[p].data();
    if (effects == nullptr) {
      state.residual_blocks.push_back(problem.AddResidualBlock(
          TriadPoseResidual::Create(poses[p].mean, mean_stddev, options.gravity_mps2), nullptr,
          result->parameters.data(), direction));
    } else {
      TriadPoseContext context;
      context.time_s = poses[p].time_s - result->time_origin_s;
      state.residual_blocks.push_back(
          problem.AddResidualBlock(TriadPoseResidual::CreateWithEffects(
                                       poses[p].mean, mean_stddev, options.gravity_mps2, context),
                                   nullptr, result->parameters.data(), effects, direction));
    }
    problem.SetManifold(direction, new ceres::SphereManifold<3>());
    state.blocks.push_back(direction);
  }
  if (effects != nullptr && static_cast<int>(estimated.size()) < kTriadEffectCoefficientCount) {
    std::vector<int> held;
    for (int c = 0; c < kTriadEffectCoefficientCount; ++c)
      if (!std::binary_search(estimated.begin(), estimated.end(), c)) held.push_back(c);
    problem.SetManifold(effects, new ceres::SubsetManifold(kTriadEffectCoefficientCount, held));
  }

  // The rank check at the initial guess first: a rank-deficient problem wanders along its null
  // space while solving, which blurs what the poses cannot determine (and the plane they lie in).
  ACCELCAL_RETURN_IF_ERROR(
      CheckIdentifiable(state, result->directions, &problem, nullptr, nullptr, result));
  // A failed solve is reported after the rank check: a rank-deficient problem often does not
  // converge, and naming what cannot be determined is the more useful refusal.
  // The directions eliminated first (DENSE_SCHUR): each step costs O(poses), not O(poses^3).
  const std::vector<double*> directions(state.blocks.end() - pose_count, state.blocks.end());
  const Status solved =
      SolveQuietlyEliminating(options.solve, directions, &problem, &result->solver);

  // At the solution: the whitened residuals, and the rank check again (the initial guess may
  // have hidden a degeneracy).
  std::vector<double> residuals;
  TriadReducedInformation reduced;
  ACCELCAL_RETURN_IF_ERROR(
      CheckIdentifiable(state, result->directions, &problem, &residuals, &reduced, result));
  result->whitened_residuals.resize(pose_count);
  result->chi2 = 0.0;
  for (int p = 0; p < pose_count; ++p) {
    for (int k = 0; k < 3; ++k) {
      result->whitened_residuals[p][k] = residuals[3 * p + k];
      result->chi2 += residuals[3 * p + k] * residuals[3 * p + k];
    }
  }
  if (!solved.ok() && !result->solver.converged) {
    // Full rank but too weakly determined to converge: poses bunched around one direction
    // (a cone of a few degrees) is the usual cause, and more iterations do not cure it. The
    // pose means' ranges show it without any parameter: a set spread over the sphere spans
    // about twice the output at 1 g on every axis.
    std::array<double, 3> low = poses[0].mean;
    std::array<double, 3> high = poses[0].mean;
    for (const TriadPoseMean& pose : poses) {
      for (int k = 0; k < 3; ++k) {
        low[k] = std::min(low[k], pose.mean[k]);
        high[k] = std::max(high[k], pose.mean[k]);
      }
    }
    // Spread over the sphere (every axis spans at least 1.5 times the output at 1 g, from the
    // smallest span: the axes' gains differ by percent), the poses may still all lie along the
    // axes: the angles, which couple two axes, are then seen through n_j n_k ~ 0 (issue 45: the
    // refusal quoted spans that satisfied its own rule). The directions, roughly: each mean
    // about the middle of its axis's span, over half the span.
    const double smallest = std::min({high[0] - low[0], high[1] - low[1], high[2] - low[2]});
    const double largest = std::max({high[0] - low[0], high[1] - low[1], high[2] - low[2]});
    if (smallest >= 0.75 * largest) {
      std::array<double, 3> coupling{};  // xy, xz, yz: the largest |n_j n_k| over the poses
      for (const TriadPoseMean& pose : poses) {
        std::array<double, 3> n;
        for (int k = 0; k < 3; ++k)
          n[k] = (pose.mean[k] - 0.5 * (high[k] + low[k])) / (0.5 * (high[k] - low[k]));
        coupling[0] = std::max(coupling[0], std::abs(n[0] * n[1]));
        coupling[1] = std::max(coupling[1], std::abs(n[0] * n[2]));
        coupling[2] = std::max(coupling[2], std::abs(n[1] * n[2]));
      }
      if (*std::max_element(coupling.begin(), coupling.end()) < 0.25) {
        return Status::Error(StringPrintf(
            "the maximum-likelihood solve did not converge in %d iterations: the %d poses span "
            "every axis (%.4g, %.4g, %.4g on x, y, z in the log's unit), but each has gravity "
            "along one axis (the largest |n_j n_k| over them: xy %.2f, xz %.2f, yz %.2f, where a "
            "pose midway between two axes has 0.5), so the misalignment angles, which couple two "
            "axes, are not determined; hold the sensor also tilted about 45 degrees between each "
            "pair of axes",
            result->solver.iterations - 1, pose_count, high[0] - low[0], high[1] - low[1],
            high[2] - low[2], coupling[0], coupling[1], coupling[2]));
      }
    }
    return Status::Error(StringPrintf(
        "the maximum-likelihood solve did not converge in %d iterations: the %d poses determine "
        "the parameters too weakly (their means span %.4g, %.4g, %.4g on x, y, z in the log's "
        "unit; poses spread over the whole sphere span about twice the output at 1 g on every "
        "axis); hold the sensor with each axis up and down, and in directions between",
        result->solver.iterations - 1, pose_count, high[0] - low[0], high[1] - low[1],
        high[2] - low[2]));
  }
  ACCELCAL_RETURN_IF_ERROR(solved.WithContext("the maximum-likelihood solve"));
  const int min_poses = MinPoses(parameter_count);
  if (pose_count < min_poses) {
    result->suggested_directions = SuggestedPoses(state, result->directions);
    return Status::Error(StringPrintf(
        "%d poses give %d residuals for %d unknowns (%d parameters and 2 per gravity direction), "
        "%d degrees of freedom: nothing is left to check the noise model; hold the sensor in at "
        "least %d poses%s",
        pose_count, 3 * pose_count, parameter_count + 2 * pose_count, parameter_count,
        pose_count - parameter_count, min_poses,
        SuggestionText(result->suggested_directions, false).c_str()));
  }

  // The covariance of the sensor parameters: the inverse of their reduced information, the
  // directions eliminated (the same marginal covariance as ceres::Covariance over every block,
  // to rounding: tests/triad_identifiability_test.cc), without an inverse over every pose.
  Eigen::MatrixXd covariance;
  if (!ReducedCovariance(reduced, &covariance)) {
    return Status::Error(StringPrintf(
        "ceres::Covariance could not invert the information of the %d triad parameters; the "
        "poses do not determine them",
        parameter_count));
  }
  for (int i = 0; i < kTriadParameterCount; ++i) {
    for (int j = 0; j < kTriadParameterCount; ++j) result->covariance[i][j] = covariance(i, j);
    result->stddev[i] = std::sqrt(result->covariance[i][i]);
  }
  // The effects' tangent coordinates are the estimated coefficients in ascending order (the
  // SubsetManifold holds the others); the held ones have no covariance.
  const int estimated_count = static_cast<int>(estimated.size());
  for (int a = 0; a < estimated_count; ++a) {
    const int c = estimated[a];
    for (int b = 0; b < estimated_count; ++b) {
      result->effects_covariance[c][estimated[b]] =
          covariance(kTriadParameterCount + a, kTriadParameterCount + b);
    }
    for (int i = 0; i < kTriadParameterCount; ++i)
      result->cross_covariance[i][c] = covariance(i, kTriadParameterCount + a);
  }
  for (int c = 0; c < kTriadEffectCoefficientCount; ++c)
    result->effects_stddev[c] = std::sqrt(std::max(result->effects_covariance[c][c], 0.0));

  result->degrees_of_freedom = pose_count - parameter_count;
  const double dof = result->degrees_of_freedom;
  result->chi2_per_dof = result->chi2 / dof;
  result->chi2_per_dof_spread = std::sqrt(2.0 / dof);
  result->p_value = ChiSquareSurvival(result->chi2, dof);
  return Status::Ok();
}

}  // namespace accelcal
