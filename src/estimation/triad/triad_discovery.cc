#include "estimation/triad/triad_discovery.h"

#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "common/format.h"
#include "estimation/discovery/selection.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/statistics/diagnostics.h"
#include "estimation/statistics/extra_chi_square.h"
#include "estimation/triad/triad_contrasts.h"
#include "estimation/triad/triad_pose_noise.h"
#include "estimation/triad/triad_shape_checks.h"
#include "residuals/triad_pose_residual.h"

namespace accelcal {
namespace {

// The fit of `poses` with the effect coefficients `effects` under the chosen noise model.
Status Fit(const std::vector<TriadPoseMean>& poses, const TriadDiscoveryOptions& options,
           const std::vector<std::array<double, 3>>& pose_mean_variance,
           const std::vector<int>& effects, TriadMlResult* result) {
  TriadMlOptions fit = options.fit;
  fit.effects = effects;
  fit.pose_mean_variance = pose_mean_variance;
  fit.suggest_poses = false;
  ACCELCAL_RETURN_IF_ERROR(CalibrateTriadMl(poses, fit, result));
  // Under the coloured model with a correlation across poses, the scatter every check and F test
  // judges is the chi-square under the pose means' full covariance (triad_pose_noise.h).
  if (pose_mean_variance.empty() || options.coloured_noise.correlation.empty()) return Status::Ok();
  double chi2 = 0.0;
  ACCELCAL_RETURN_IF_ERROR(TriadCorrelatedChi2(poses, *result, options.coloured_noise.correlation,
                                               options.fit.quantisation_variance,
                                               options.fit.gravity_mps2, &chi2, nullptr));
  result->chi2 = chi2;
  result->chi2_per_dof = chi2 / result->degrees_of_freedom;
  result->p_value = ChiSquareSurvival(chi2, result->degrees_of_freedom);
  return Status::Ok();
}

// The p-value of the chi-square `smaller` removes from `larger` with one parameter more, as an
// F test against the larger model's own residual scatter.
double ExtensionPValue(const TriadMlResult& smaller, const TriadMlResult& larger) {
  const double delta = std::max(smaller.chi2 - larger.chi2, 0.0);
  const double scatter = larger.chi2 / larger.degrees_of_freedom;
  if (!(scatter > 0.0)) return delta > 0.0 ? 0.0 : 1.0;
  return FSurvival(delta / scatter, 1.0, larger.degrees_of_freedom);
}

// The coefficients static poses can determine, one candidate each; and those they cannot,
// grouped by effect.
void SplitCandidates(std::vector<int>* testable, std::vector<std::vector<int>>* untestable) {
  const std::vector<TriadEffectCoefficient> list = TriadEffectCoefficientList();
  const auto infos = TriadEffectInfos();
  int previous_effect = -1;
  for (size_t c = 0; c < list.size(); ++c) {
    const TriadEffectInfo& info = infos[list[c].effect];
    if (info.confounded_with[0] == '\0') {
      testable->push_back(static_cast<int>(c));
    } else {
      if (list[c].effect != previous_effect) untestable->emplace_back();
      untestable->back().push_back(static_cast<int>(c));
    }
    previous_effect = list[c].effect;
  }
}

// The poses' indices in the order they were held (by mid-time).
std::vector<int> PosesInTimeOrder(const std::vector<TriadPoseMean>& poses) {
  std::vector<int> order(poses.size());
  for (size_t p = 0; p < poses.size(); ++p) order[p] = static_cast<int>(p);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return poses[a].time_s < poses[b].time_s; });
  return order;
}

// The specific force `fit`'s parameters and quadratic scale terms make of an output (the
// log's unit in, m/s^2 out); false when the output is outside what they can invert.
bool CalibratedForce(const TriadMlResult& fit, const std::array<double, 3>& output,
                     double force[3]) {
  const int first_k2 = TriadEffectCoefficientIndex("scale_nonlinearity_x");
  return TriadSpecificForce(fit.parameters.data(), &fit.effects[first_k2], output.data(), force);
}

// The direction of a held-out pose fitted with the parameters and effects of `fit` held;
// returns its whitened chi-square (3 residuals, 2 unknowns).
double HeldOutChi2(const TriadPoseMean& pose, const std::array<double, 3>& mean_stddev,
                   const TriadMlResult& fit, double gravity_mps2) {
  TriadParameters parameters = fit.parameters;
  TriadEffectCoefficients effects = fit.effects;
  double force[3] = {0.0, 0.0, 0.0};
  std::array<double, 3> direction = {0.0, 0.0, 1.0};
  if (CalibratedForce(fit, pose.mean, force)) {
    const double norm = std::sqrt(force[0] * force[0] + force[1] * force[1] + force[2] * force[2]);
    if (norm > 0.0 && std::isfinite(norm))
      for (int k = 0; k < 3; ++k) direction[k] = force[k] / norm;
  }
  TriadPoseContext context;
  context.time_s = pose.time_s - fit.time_origin_s;
  ceres::Problem problem;
  problem.AddResidualBlock(
      TriadPoseResidual::CreateWithEffects(pose.mean, mean_stddev, gravity_mps2, context), nullptr,
      parameters.data(), effects.data(), direction.data());
  problem.SetParameterBlockConstant(parameters.data());
  problem.SetParameterBlockConstant(effects.data());
  problem.SetManifold(direction.data(), new ceres::SphereManifold<3>());
  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = 50;
  solver_options.function_tolerance = 1e-14;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-14;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  return 2.0 * summary.final_cost;
}

// Leave-poses-out cross-validation of the model with `effects`: mean held-out chi-square per
// pose. Poses are dealt to folds in time order (pose p to fold p mod folds).
Status CrossValidate(const std::vector<TriadPoseMean>& poses, const TriadDiscoveryOptions& options,
                     const std::vector<std::array<double, 3>>& pose_mean_variance,
                     const std::array<double, 3>& white_variance, const std::vector<int>& effects,
                     double* mean_chi2) {
  const int folds = options.cross_validation_folds;
  const std::vector<int> order = PosesInTimeOrder(poses);
  double sum = 0.0;
  for (int fold = 0; fold < folds; ++fold) {
    std::vector<TriadPoseMean> training;
    std::vector<std::array<double, 3>> training_variance;
    std::vector<int> held;
    for (size_t i = 0; i < order.size(); ++i) {
      const int p = order[i];
      if (static_cast<int>(i) % folds == fold) {
        held.push_back(p);
      } else {
        training.push_back(poses[p]);
        if (!pose_mean_variance.empty()) training_variance.push_back(pose_mean_variance[p]);
      }
    }
    TriadMlResult fit;
    ACCELCAL_RETURN_IF_ERROR(Fit(training, options, training_variance, effects, &fit));
    for (const int p : held) {
      std::array<double, 3> stddev;
      for (int k = 0; k < 3; ++k) {
        stddev[k] =
            std::sqrt((pose_mean_variance.empty() ? white_variance[k] / poses[p].sample_count
                                                  : pose_mean_variance[p][k]) +
                      options.fit.quantisation_variance[k]);
      }
      sum += HeldOutChi2(poses[p], stddev, fit, options.fit.gravity_mps2);
    }
  }
  *mean_chi2 = sum / static_cast<double>(poses.size());
  return Status::Ok();
}

// omega_k^2 >= 0 with sum_p r_p,k^2 / (v_p,k + omega_k^2) = dof / 3: the per-pose offset
// wander that would bring the axis's share of the chi-square to its expectation.
std::array<double, 3> PoseWander(const TriadMlResult& fit) {
  std::array<double, 3> wander{};
  const double target = fit.degrees_of_freedom / 3.0;
  for (int k = 0; k < 3; ++k) {
    auto chi2 = [&](double extra) {
      double sum = 0.0;
      for (size_t p = 0; p < fit.whitened_residuals.size(); ++p) {
        const double v = fit.mean_stddev[p][k] * fit.mean_stddev[p][k];
        const double raw = fit.whitened_residuals[p][k] * fit.mean_stddev[p][k];
        sum += raw * raw / (v + extra);
      }
      return sum;
    };
    if (chi2(0.0) <= target) continue;
    double low = 0.0;
    double high = 1.0;
    while (chi2(high) > target && high < 1e30) high *= 4.0;
    for (int i = 0; i < 200; ++i) {
      const double middle = 0.5 * (low + high);
      (chi2(middle) > target ? low : high) = middle;
    }
    wander[k] = std::sqrt(0.5 * (low + high));
  }
  return wander;
}

// The lag-1 statistic of residuals in time order, self-normalised: N(0, 1) when they are
// independent. `in_time_order`: each pose's residuals, the poses in time order.
struct Lag1 {
  double r = 0.0;  // the correlation
  double z = 0.0;
};
Lag1 LagOneCorrelation(const std::vector<std::vector<double>>& in_time_order) {
  double products = 0.0, squares = 0.0, norm = 0.0;
  for (size_t i = 0; i + 1 < in_time_order.size(); ++i) {
    for (size_t k = 0; k < in_time_order[i].size(); ++k) {
      const double a = in_time_order[i][k];
      const double b = in_time_order[i + 1][k];
      products += a * b;
      squares += a * a * b * b;
    }
  }
  for (const auto& residuals : in_time_order)
    for (const double r : residuals) norm += r * r;
  Lag1 lag;
  lag.r = norm > 0.0 ? products / norm : 0.0;
  lag.z = squares > 0.0 ? products / std::sqrt(squares) : 0.0;
  return lag;
}

// The chi-square `shape` removes from `fit` by backfitting: three rounds of its coefficients at
// the current fit's contrasts, those offsets taken out of the pose means, and the model refitted;
// the gain is the fit's chi-square less the last refit's.
Status RefittedGain(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                    const std::vector<std::array<double, 3>>& pose_mean_variance,
                    const std::vector<int>& effects, const TriadPoseCorrelation& correlation,
                    const TriadDiscoveryOptions& options, const TriadShapeCheck& shape,
                    double* gain) {
  std::vector<TriadPoseMean> shifted = poses;
  TriadMlResult current = fit;
  for (int round = 0; round < 3; ++round) {
    TriadContrasts contrasts;
    ACCELCAL_RETURN_IF_ERROR(
        TriadPoseContrasts(shifted, current, options.fit.gravity_mps2, &contrasts));
    const TriadContrastWhitener whitener(shifted, current, contrasts, correlation,
                                         options.fit.quantisation_variance);
    Eigen::MatrixXd whitened, columns;
    ACCELCAL_RETURN_IF_ERROR(whitener.Whiten(contrasts.rows, &whitened));
    ACCELCAL_RETURN_IF_ERROR(
        whitener.Whiten(TriadOffsetColumns(shape.offsets, contrasts.normals), &columns));
    const Eigen::MatrixXd model = whitened.rightCols(whitened.cols() - 1);
    const Eigen::VectorXd beta = ProjectedCoefficients(model, columns, whitened.col(0));
    for (size_t c = 0; c < shape.offsets.size(); ++c)
      for (size_t p = 0; p < shifted.size(); ++p)
        for (int k = 0; k < 3; ++k) shifted[p].mean[k] -= beta[c] * shape.offsets[c](p, k);
    ACCELCAL_RETURN_IF_ERROR(Fit(shifted, options, pose_mean_variance, effects, &current));
  }
  *gain = fit.chi2 - current.chi2;
  return Status::Ok();
}

// A full-scale shape too large for the linearisation at the fit (a clipped axis moves the fit's
// scale and directions, and which poses the hinge should hold is then misjudged): the top j poses
// along +-n_k (j = 2 to 12, as the check's hinges) left out and the model refitted to the others,
// each left-out pose's calibrated magnitude under the refit short of g. The best by BIC (the
// refit's chi-square, j free poses) with `effects` or with none; `gain` the fit's chi-square less
// the refit's, `rank` j, and the sentence.
struct Deletion {
  double gain = 0.0;
  double shortfall_mps2 = 0.0;  // the largest left-out pose's, in magnitude
  double left = 0.0;            // the refit's chi-square
  int rank = 0;
  bool without_effects = false;
  std::string description;
};
Status FullScaleByDeletion(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                           const std::vector<std::array<double, 3>>& pose_mean_variance,
                           const std::vector<int>& effects, const TriadDiscoveryOptions& options,
                           int axis, Deletion* best) {
  const double log_n = std::log(static_cast<double>(poses.size()));
  double best_bic = HUGE_VAL;
  std::vector<std::pair<int, int>> candidates;  // (sign, j)
  std::vector<std::vector<int>> sorted(2);
  for (int s = 0; s < 2; ++s) {
    const int sign = s == 0 ? 1 : -1;
    for (size_t p = 0; p < poses.size(); ++p)
      if (sign * fit.directions[p][axis] > 0.5) sorted[s].push_back(static_cast<int>(p));
    std::sort(sorted[s].begin(), sorted[s].end(), [&](int a, int b) {
      return sign * fit.directions[a][axis] > sign * fit.directions[b][axis];
    });
    for (int j = 2; j <= std::min<int>(12, static_cast<int>(sorted[s].size())); ++j)
      candidates.push_back({s, j});
  }
  for (const auto& [s, j] : candidates) {
    std::vector<char> out(poses.size(), 0);
    for (int i = 0; i < j; ++i) out[sorted[s][i]] = 1;
    std::vector<TriadPoseMean> kept;
    std::vector<std::array<double, 3>> kept_variance;
    for (size_t p = 0; p < poses.size(); ++p) {
      if (out[p]) continue;
      kept.push_back(poses[p]);
      if (!pose_mean_variance.empty()) kept_variance.push_back(pose_mean_variance[p]);
    }
    for (const bool with : {true, false}) {
      if (!with && effects.empty()) continue;
      TriadMlResult refit;
      if (!Fit(kept, options, kept_variance, with ? effects : std::vector<int>{}, &refit).ok())
        continue;
      // Every left-out pose short of g under the refit, and by how much at most.
      bool short_of_g = true;
      double largest = 0.0;
      for (int i = 0; i < j && short_of_g; ++i) {
        const TriadPoseMean& pose = poses[sorted[s][i]];
        double force[3];
        if (!CalibratedForce(refit, pose.mean, force)) {
          short_of_g = false;
          break;
        }
        const double shortfall =
            options.fit.gravity_mps2 -
            std::sqrt(force[0] * force[0] + force[1] * force[1] + force[2] * force[2]);
        short_of_g = shortfall > 0.0;
        largest = std::max(largest, shortfall);
      }
      if (!short_of_g) continue;
      const double penalty = (with ? 0.0 : effects.size()) * log_n;
      const double bic = refit.chi2 + j * log_n - penalty;
      if (bic < best_bic) {
        best_bic = bic;
        best->gain = fit.chi2 - refit.chi2 + penalty;
        best->left = refit.chi2;
        best->shortfall_mps2 = largest;
        best->rank = j;
        best->without_effects = !with;
        const char a = "xyz"[axis];
        const double lowest = std::abs(fit.directions[sorted[s][j - 1]][axis]);
        best->description = StringPrintf(
            "the %d poses nearest %c1 g on %c (|n_%c| >= %.3f) fall short of the model fitted to "
            "the other poses, by up to %.3g m/s^2 in magnitude (the fit's chi2 falls by %.4g when "
            "they are left out)",
            j, s == 0 ? '+' : '-', a, a, lowest, largest, fit.chi2 - refit.chi2);
      }
    }
  }
  return Status::Ok();
}

// Each shape's size for the naming (CheckWhatRemains): the chi-square it removes and the columns
// it costs. Where the pose means scatter beyond the noise model, a flagged shape may be too large
// for the linearisation at the fit (a clipped axis moves the fit's scale and directions): its
// gain is then what it removes when its offsets are taken out of the pose means and the model
// refitted (RefittedGain), and a full-scale shape's what leaving its poses out does
// (FullScaleByDeletion, which also rewrites its sentence). Either is also tried with none of the
// effects forward selection found (a catalogue effect can pay for part of a shape it does not
// have: a scale nonlinearity for a clipped axis), the effects' columns counted against it;
// `without_effects` when that is the better (the gain then counts the effects' columns saved).
struct ShapeGains {
  std::vector<double> gain;
  std::vector<double> left;  // the chi-square left with the shape, as fitted
  std::vector<int> rank;
  std::vector<char> without_effects;
};
ShapeGains GainsForNaming(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                          const std::vector<std::array<double, 3>>& pose_mean_variance,
                          const std::vector<int>& effects, const TriadPoseCorrelation& correlation,
                          const TriadDiscoveryOptions& options,
                          const std::vector<TriadShapeCheck>& shapes,
                          TriadDiscoveryResult* result) {
  ShapeGains gains;
  gains.gain.assign(shapes.size(), 0.0);
  gains.left.assign(shapes.size(), 0.0);
  gains.rank.assign(shapes.size(), 0);
  gains.without_effects.assign(shapes.size(), 0);
  const double log_n = std::log(static_cast<double>(poses.size()));
  const double effects_cost = effects.size() * log_n;
  for (size_t i = 0; i < shapes.size(); ++i) {
    gains.gain[i] = shapes[i].check.statistic;
    gains.left[i] = std::max(0.0, fit.chi2 - shapes[i].check.statistic);
    gains.rank[i] = static_cast<int>(shapes[i].check.dof);
    if (!result->checks[0].flagged || !result->checks[2 + i].flagged) continue;
    if (shapes[i].check.shape_class == ShapeClass::kFullScale) {
      Deletion deletion;
      if (FullScaleByDeletion(poses, fit, pose_mean_variance, effects, options,
                              shapes[i].check.axis, &deletion)
              .ok() &&
          deletion.rank > 0 &&
          deletion.gain - deletion.rank * log_n > gains.gain[i] - gains.rank[i] * log_n) {
        gains.gain[i] = deletion.gain;
        gains.left[i] = deletion.left;
        gains.rank[i] = deletion.rank;
        gains.without_effects[i] = deletion.without_effects;
        ResidualCheck& check = result->checks[2 + i];
        check.description = deletion.description + " (" + check.description + ")";
        check.advice = TriadFullScaleAdvice(check.axis, deletion.shortfall_mps2);
      }
      continue;
    }
    if (shapes[i].offsets.empty()) continue;
    double refitted = 0.0;
    if (RefittedGain(poses, fit, pose_mean_variance, effects, correlation, options, shapes[i],
                     &refitted)
            .ok() &&
        refitted > gains.gain[i]) {
      gains.gain[i] = refitted;
      gains.left[i] = std::max(0.0, fit.chi2 - refitted);
    }
    if (effects.empty()) continue;
    if (RefittedGain(poses, fit, pose_mean_variance, {}, correlation, options, shapes[i], &refitted)
            .ok() &&
        refitted + effects_cost > gains.gain[i]) {
      // Without the effects the model has their columns fewer: BIC counts them as gain.
      gains.without_effects[i] = 1;
      gains.gain[i] = refitted + effects_cost;
      gains.left[i] = std::max(0.0, fit.chi2 - refitted);
    }
  }
  return gains;
}

// Step 3: the checks of what the final model leaves, Holm at `alpha`: the chi-square and the
// lag-1 correlation (no shape: the scatter and the wander), and the shapes of
// triad_shape_checks.h. Then what remains in words (below, "In words"): what fits best first,
// a shape or the scatter ("offsets that jump from pose to pose"), the others when they stand
// beyond what is named; the wander when it stands on what the shapes leave.
Status CheckWhatRemains(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                        const std::vector<std::array<double, 3>>& pose_mean_variance,
                        const std::vector<int>& effects, const TriadPoseCorrelation& correlation,
                        const TriadDiscoveryOptions& options, double alpha,
                        TriadDiscoveryResult* result) {
  // The contrasts, whitened under the noise model, and their residual at its minimum.
  TriadContrasts contrasts;
  ACCELCAL_RETURN_IF_ERROR(TriadPoseContrasts(poses, fit, options.fit.gravity_mps2, &contrasts));
  const TriadContrastWhitener whitener(poses, fit, contrasts, correlation,
                                       options.fit.quantisation_variance);
  Eigen::MatrixXd whitened;
  ACCELCAL_RETURN_IF_ERROR(whitener.Whiten(contrasts.rows, &whitened));
  const Eigen::MatrixXd model = whitened.rightCols(whitened.cols() - 1);
  const Eigen::VectorXd z = whitened.col(0);
  const Eigen::VectorXd residual =
      z - model * Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(model).solve(z);

  ResidualCheck chi2;
  chi2.name = "chi2";
  chi2.statistic = fit.chi2_per_dof;
  chi2.dof = fit.degrees_of_freedom;
  chi2.p_value = ChiSquareSurvival(fit.chi2, fit.degrees_of_freedom);
  chi2.shape_class = ShapeClass::kPoseOrder;
  chi2.description = StringPrintf(
      "the pose means scatter more than the noise model says: chi2/dof = %.3g on %d dof "
      "(expected 1 +- %.2g, p = %.3g)",
      fit.chi2_per_dof, fit.degrees_of_freedom, fit.chi2_per_dof_spread, chi2.p_value);

  // Consecutive poses in time: under the correlated model its whitened residuals (one per pose,
  // time order); else the fit's own three per pose, independent under its model.
  std::vector<std::vector<double>> in_time_order;
  if (!correlation.empty()) {
    for (int j = 0; j < residual.size(); ++j) in_time_order.push_back({residual[j]});
  } else {
    for (const int p : PosesInTimeOrder(poses)) {
      const auto& r = fit.whitened_residuals[p];
      in_time_order.push_back({r[0], r[1], r[2]});
    }
  }
  const Lag1 lag1 = LagOneCorrelation(in_time_order);
  ResidualCheck lag;
  lag.name = "pose_lag1_correlation";
  lag.statistic = lag1.r;
  lag.p_value = std::erfc(std::abs(lag1.z) / std::sqrt(2.0));
  // What the correlation found, by its sign: alike neighbours are a slow wander; alternating
  // ones are not (something that flips between consecutive poses: the order the orientations
  // were held in, a hysteresis, an effect of the pose's direction the model lacks).
  if (lag.statistic >= 0.0) {
    lag.shape_class = ShapeClass::kTime;
    lag.description = StringPrintf(
        "consecutive poses' residuals are alike: lag-1 correlation r = %+.2f (z = %.2f, p = "
        "%.3g), the offsets wander slowly from pose to pose",
        lag.statistic, lag1.z, lag.p_value);
    lag.advice =
        "a bias that wanders over minutes (flicker noise slower than the poses, or temperature): "
        "hold shorter poses closer together, or log temperature";
  } else {
    lag.shape_class = ShapeClass::kPoseOrder;
    lag.description = StringPrintf(
        "consecutive poses' residuals alternate in sign: lag-1 correlation r = %+.2f (z = %.2f, "
        "p = %.3g), not a slow wander but something that flips from one pose to the next",
        lag.statistic, lag1.z, lag.p_value);
    lag.advice =
        "the order the orientations were held in, hysteresis, or an effect of the pose's "
        "direction the model lacks: hold the orientations in another order and compare";
  }

  TriadShapeContext context;
  context.unit = options.unit;
  context.gain_mps2_per_unit = options.gain_mps2_per_unit;
  std::vector<TriadShapeCheck> shapes;
  ACCELCAL_RETURN_IF_ERROR(
      TriadShapeChecks(poses, fit, contrasts, whitener, model, residual, context, &shapes));
  result->checks = {chi2, lag};
  for (const TriadShapeCheck& shape : shapes) result->checks.push_back(shape.check);
  FlagByHolm(alpha, &result->checks);
  if (result->checks[0].flagged) result->pose_wander = PoseWander(fit);

  const ShapeGains gains =
      GainsForNaming(poses, fit, pose_mean_variance, effects, correlation, options, shapes, result);
  const std::vector<double>& gain = gains.gain;
  const std::vector<int>& bic_rank = gains.rank;
  const std::vector<char>& without = gains.without_effects;

  // In words. What fits best comes first, by BIC on the whitened contrasts: a shape alone (the
  // chi-square it leaves, log n per column, and 2 log of its candidates for the maxima) against
  // offsets that jump from pose to pose (one variance more, fitted: dof (1 + log(chi2 / dof)) +
  // log n). After a shape, each further one is named when it stands beyond those named (its
  // chi-square tail at alpha over the checks), and the scatter when what they leave still
  // scatters; after the jumps, a shape only when it stands against that scatter (an F test).
  const double each = alpha / static_cast<double>(result->checks.size());
  const double total = fit.chi2;
  const int dof = std::max(1, fit.degrees_of_freedom);
  const double log_n = std::log(static_cast<double>(poses.size()));
  std::vector<int> flagged_shapes;
  for (size_t i = 0; i < shapes.size(); ++i)
    if (result->checks[2 + i].flagged) flagged_shapes.push_back(static_cast<int>(i));
  auto shape_bic = [&](int i) {
    return total - gain[i] + bic_rank[i] * log_n +
           2.0 * std::log(static_cast<double>(shapes[i].candidates));
  };
  std::stable_sort(flagged_shapes.begin(), flagged_shapes.end(),
                   [&](int a, int b) { return shapes[a].check.p_value < shapes[b].check.p_value; });
  if (!flagged_shapes.empty()) {
    const auto best = std::min_element(flagged_shapes.begin(), flagged_shapes.end(),
                                       [&](int a, int b) { return shape_bic(a) < shape_bic(b); });
    std::rotate(flagged_shapes.begin(), best, best + 1);
  }
  const bool scatter = result->checks[0].flagged && total > dof;
  const double jumps_bic = dof * (1.0 + std::log(total / dof)) + log_n;
  // A shape comes before the jumps only if it also stands against what it leaves (an F test at
  // 0.05): on a few degrees of freedom, a family of almost as many columns takes most of any
  // scatter.
  auto stands_against_scatter = [&](int i) {
    const int left_dof = dof - gains.rank[i];
    if (left_dof < 1) return false;
    const double f = (total - gains.left[i]) / gains.rank[i] /
                     (std::max(gains.left[i], 1e-12 * total) / left_dof);
    return FSurvival(f, gains.rank[i], left_dof) <= 0.05;
  };
  const bool jumps_first =
      scatter && (flagged_shapes.empty() || jumps_bic < shape_bic(flagged_shapes.front()) ||
                  !stands_against_scatter(flagged_shapes.front()));
  if (jumps_first) {
    std::stable_sort(flagged_shapes.begin(), flagged_shapes.end(), [&](int a, int b) {
      return shapes[a].check.p_value < shapes[b].check.p_value;
    });
  }

  Eigen::MatrixXd kept(model.rows(), 0);
  int kept_rank = 0;
  double removed = 0.0;    // the chi-square the kept shapes remove
  std::vector<int> named;  // indices into result->checks
  std::string parts;
  if (jumps_first) named.push_back(0);
  for (const int i : flagged_shapes) {
    bool stands = kept.cols() == 0 && !jumps_first;
    if (!stands) {
      Eigen::MatrixXd both(model.rows(), model.cols() + kept.cols());
      both << model, kept;
      int rank = 0;
      const double delta = ExtraChiSquare(both, shapes[i].columns, residual, &rank);
      if (jumps_first) {
        const int left = dof - kept_rank - rank;
        const double rest = residual.squaredNorm() - removed - delta;
        stands = rank > 0 && left > 0 && rest > 0.0 &&
                 std::min(1.0, shapes[i].candidates *
                                   FSurvival((delta / rank) / (rest / left), rank, left)) <= each;
      } else {
        stands = rank > 0 &&
                 std::min(1.0, shapes[i].candidates * ChiSquareSurvival(delta, rank)) <= each;
      }
    }
    if (!stands) {
      parts += (parts.empty() ? "" : ", ") + shapes[i].check.name;
      continue;
    }
    named.push_back(2 + i);
    Eigen::MatrixXd grown(model.rows(), kept.cols() + shapes[i].columns.cols());
    grown << kept, shapes[i].columns;
    kept = grown;
    removed = ExtraChiSquare(model, kept, residual, &kept_rank);
  }
  // What the kept shapes leave of the residual.
  Eigen::VectorXd left = residual;
  if (kept.cols() > 0) {
    Eigen::MatrixXd both(model.rows(), model.cols() + kept.cols());
    both << model, kept;
    left = residual -
           both * Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(both).solve(residual);
  }
  if (result->checks[0].flagged) {
    const int left_dof = std::max(1, dof - kept_rank);
    const bool stands =
        jumps_first ||
        ChiSquareSurvival(std::max(residual.squaredNorm() - removed, 0.0), left_dof) <= each;
    if (stands) {
      ResidualCheck& check = result->checks[0];
      const auto& w = result->pose_wander;
      const auto& g = options.gain_mps2_per_unit;
      check.description += StringPrintf(
          ", %s: offsets that jump from pose to pose by about (%.3g, %.3g, %.3g) %s = (%.2g, "
          "%.2g, %.2g) m/s^2 would account for it",
          jumps_first ? "not as one shape in orientation, time or order"
                      : "also beyond the shapes named",
          w[0], w[1], w[2], options.unit.c_str(), w[0] * g[0], w[1] * g[1], w[2] * g[2]);
      check.advice =
          "was the sensor disturbed between poses, or is the noise model short (a bias that "
          "wanders more slowly than the poses)? Hold each pose longer and the sensor firmly";
      if (!jumps_first) named.push_back(0);
    } else {
      parts += (parts.empty() ? "" : ", ") + std::string("chi2");
    }
  }
  if (result->checks[1].flagged) {
    bool stands = true;
    if (kept.cols() > 0) {
      std::vector<std::vector<double>> rest;
      for (int j = 0; j < left.size(); ++j) rest.push_back({left[j]});
      stands = std::erfc(std::abs(LagOneCorrelation(rest).z) / std::sqrt(2.0)) <= each;
    }
    if (stands) {
      named.push_back(1);
    } else {
      parts += (parts.empty() ? "" : ", ") + std::string("pose_lag1_correlation");
    }
  }
  result->remaining_checks = named;
  if (!named.empty() && named.front() >= 2 && without[named.front() - 2]) {
    for (const int c : effects)
      result->explained_by_shape.push_back(TriadEffectCoefficientList()[c].name);
  }
  for (const int i : named) result->remaining.push_back(WhatRemains(result->checks[i]));
  if (!parts.empty())
    result->remaining.push_back("also flagged, but not beyond what is named above: " + parts);
  return Status::Ok();
}

// Step 3's other tail, beside the verdict: a chi-square too small for its degrees of freedom.
// It is about the weights of the fit and its sigmas, so it is the fit's own chi-square (its
// whitened residuals' squares), also when the scatter is judged under the correlation across
// poses.
ResidualCheck CheckNoiseOverstated(const TriadMlResult& fit, double alpha) {
  double own = 0.0;
  for (const auto& r : fit.whitened_residuals)
    for (int k = 0; k < 3; ++k) own += r[k] * r[k];
  const double chi2_per_dof = own / fit.degrees_of_freedom;
  ResidualCheck check;
  check.name = "chi2_lower_tail";
  check.statistic = chi2_per_dof;
  check.dof = fit.degrees_of_freedom;
  check.p_value = ChiSquareCdf(own, fit.degrees_of_freedom);
  check.flagged = check.p_value < alpha;
  check.description = StringPrintf(
      "the pose means scatter less than the noise model says: chi2/dof = %.3g on %d dof (p = "
      "%.3g in the lower tail); the noise model overstates a pose mean's variance (noise "
      "anti-correlated within a pose, or variance that averages out over a pose), so the sigmas "
      "are conservative, by a factor of about %.2g",
      chi2_per_dof, fit.degrees_of_freedom, check.p_value,
      1.0 / std::sqrt(std::max(chi2_per_dof, 1e-12)));
  return check;
}

// The triad's poses as a geometry of the one discovery procedure
// (estimation/discovery/selection.h): the maximum-likelihood fit of the pose means with a set of
// effect coefficients under the chosen noise model, each candidate refitted and tested by the F
// test of ExtensionPValue. Candidates are indices into `testable` (coefficients static poses can
// determine).
class TriadGeometry : public DiscoveryGeometry {
 public:
  TriadGeometry(const std::vector<TriadPoseMean>& poses, const TriadDiscoveryOptions& options,
                const std::vector<std::array<double, 3>>& noise, std::vector<int> testable,
                const TriadMlResult& baseline)
      : poses_(poses),
        options_(options),
        noise_(noise),
        testable_(std::move(testable)),
        current_(baseline) {}

  // What each tested candidate's fit gave, in the order they were tested (the scores' order).
  struct Detail {
    double estimate = 0.0;
    double stddev = 0.0;
    double f = 0.0;
  };
  const std::vector<Detail>& details() const { return details_; }
  const TriadMlResult& current() const { return current_; }
  int Coefficient(int candidate) const { return testable_[candidate]; }
  std::vector<int> Coefficients() const {
    std::vector<int> coefficients;
    for (const int c : model_) coefficients.push_back(testable_[c]);
    return coefficients;
  }
  // The model's effects in the coefficients' order (how the report lists them).
  void SortEffects() { std::sort(model_.begin(), model_.end()); }

  // A candidate whose fit would leave no degree of freedom, or that cannot be fitted, is not
  // tested: it is listed as not testable, with why, rather than scored 0 +- 0, p = 1.
  Status TestCandidates(const std::vector<int>& candidates,
                        std::vector<CandidateTest>* tests) override {
    tests->assign(candidates.size(), CandidateTest());
    fits_.assign(candidates.size(), TriadMlResult());
    tested_candidates_ = candidates;
    const int dof_left = current_.degrees_of_freedom - 1;
    for (size_t i = 0; i < candidates.size(); ++i) {
      CandidateTest& test = (*tests)[i];
      if (dof_left < 1) {
        test.tested = false;
        test.not_tested = StringPrintf(
            "not testable with the degrees of freedom left: the fit with it would leave %d (%d "
            "poses, 9 parameters, %zu effects, 2 direction angles per pose), and its F test "
            "needs at least 1",
            dof_left, current_.pose_count, model_.size() + 1);
        continue;
      }
      std::vector<int> extended = Coefficients();
      extended.push_back(testable_[candidates[i]]);
      const Status status = Fit(poses_, options_, noise_, extended, &fits_[i]);
      if (!status.ok()) {
        test.tested = false;
        test.not_tested = "not testable: the fit with it fails (" + status.message() + ")";
        continue;
      }
      test.delta_chi2 = current_.chi2 - fits_[i].chi2;
      test.p_value = ExtensionPValue(current_, fits_[i]);
      const int coefficient = testable_[candidates[i]];
      details_.push_back({fits_[i].effects[coefficient], fits_[i].effects_stddev[coefficient],
                          test.delta_chi2 / (fits_[i].chi2 / fits_[i].degrees_of_freedom)});
    }
    return Status::Ok();
  }

  // The fit TestCandidates made with it.
  Status Add(int candidate, double* delta_chi2) override {
    const auto at = std::find(tested_candidates_.begin(), tested_candidates_.end(), candidate);
    if (at == tested_candidates_.end()) return Status::Error("a candidate not tested");
    const TriadMlResult& fit = fits_[at - tested_candidates_.begin()];
    *delta_chi2 = current_.chi2 - fit.chi2;
    current_ = fit;
    model_.push_back(candidate);
    return Status::Ok();
  }

  Status TestEffects(std::vector<CandidateTest>* tests) override {
    tests->assign(model_.size(), {true, HUGE_VAL, 0.0, ""});
    for (size_t e = 0; e < model_.size(); ++e) {
      TriadMlResult reduced;
      if (Fit(poses_, options_, noise_, Without(e), &reduced).ok()) {
        (*tests)[e].delta_chi2 = reduced.chi2 - current_.chi2;
        (*tests)[e].p_value = ExtensionPValue(reduced, current_);
      }
    }
    return Status::Ok();
  }

  Status Drop(size_t effect) override {
    TriadMlResult reduced;
    ACCELCAL_RETURN_IF_ERROR(Fit(poses_, options_, noise_, Without(effect), &reduced));
    current_ = reduced;
    model_.erase(model_.begin() + effect);
    return Status::Ok();
  }

  const std::vector<int>& Effects() const override { return model_; }

  bool Swap(size_t effect, int candidate, SwapFit* swap) override {
    std::vector<int> swapped = Without(effect);
    swapped.push_back(testable_[candidate]);
    TriadMlResult fit;
    if (!Fit(poses_, options_, noise_, swapped, &fit).ok()) return false;
    swap->worse = fit.chi2 - current_.chi2;
    swap->estimate = fit.effects[testable_[candidate]];
    swap->stddev = fit.effects_stddev[testable_[candidate]];
    for (size_t e = 0; e < model_.size(); ++e) {
      const int c = testable_[model_[e]];
      swap->current_estimates.push_back(current_.effects[c]);
      swap->current_stddevs.push_back(current_.effects_stddev[c]);
      swap->estimates.push_back(e == effect ? current_.effects[c] : fit.effects[c]);
      swap->stddevs.push_back(e == effect ? current_.effects_stddev[c] : fit.effects_stddev[c]);
    }
    return true;
  }

  // Within ambiguity_delta_chi2 in units of the residual scatter.
  bool FitsAboutAsWell(const SwapFit& swap) const override {
    const double scatter = std::max(1.0, current_.chi2 / current_.degrees_of_freedom);
    return swap.worse < options_.ambiguity_delta_chi2 * scatter;
  }

  bool LooksAlike(size_t, const SwapFit& swap, double, size_t) const override {
    return FitsAboutAsWell(swap);
  }

  // The model with `candidate` beside its effects; its gain in units of the grown model's
  // residual scatter (when above 1), as the F tests judge it.
  bool Beside(int candidate, BesideFit* beside) override {
    if (current_.degrees_of_freedom - 1 < 1) return false;
    std::vector<int> grown = Coefficients();
    grown.push_back(testable_[candidate]);
    TriadMlResult fit;
    if (!Fit(poses_, options_, noise_, grown, &fit).ok()) return false;
    const double scatter = std::max(1.0, fit.chi2 / fit.degrees_of_freedom);
    beside->gain = std::max(0.0, current_.chi2 - fit.chi2) / scatter;
    for (const int e : model_) {
      const int c = testable_[e];
      beside->current_estimates.push_back(current_.effects[c]);
      beside->current_stddevs.push_back(current_.effects_stddev[c]);
      beside->estimates.push_back(fit.effects[c]);
      beside->stddevs.push_back(fit.effects_stddev[c]);
    }
    beside->estimate = fit.effects[testable_[candidate]];
    beside->stddev = fit.effects_stddev[testable_[candidate]];
    return true;
  }

 private:
  std::vector<int> Without(size_t effect) const {
    std::vector<int> without;
    for (size_t e = 0; e < model_.size(); ++e)
      if (e != effect) without.push_back(testable_[model_[e]]);
    return without;
  }

  const std::vector<TriadPoseMean>& poses_;
  const TriadDiscoveryOptions& options_;
  const std::vector<std::array<double, 3>>& noise_;
  const std::vector<int> testable_;
  TriadMlResult current_;
  std::vector<int> model_;
  std::vector<int> tested_candidates_;
  std::vector<TriadMlResult> fits_;
  std::vector<Detail> details_;
};

}  // namespace

Status DiscoverTriad(const std::vector<TriadPoseMean>& poses, const TriadDiscoveryOptions& options,
                     TriadDiscoveryResult* result) {
  *result = TriadDiscoveryResult();
  if (!options.fit.effects.empty() || options.fit.scale_nonlinearity ||
      !options.fit.pose_mean_variance.empty()) {
    return Status::Error("discovery chooses the effects and the noise model itself");
  }
  if (!(options.alpha > 0.0 && options.alpha < 0.5))
    return Status::Error(StringPrintf("alpha = %g is not in (0, 0.5)", options.alpha));
  const std::vector<TriadEffectCoefficient> coefficients = TriadEffectCoefficientList();

  // 1. The noise model of the pose means.
  ACCELCAL_RETURN_IF_ERROR(Fit(poses, options, {}, {}, &result->white));
  std::vector<std::array<double, 3>> noise;
  const TriadNoiseCandidate& coloured = options.coloured_noise;
  if (!coloured.pose_mean_variance.empty()) {
    if (coloured.pose_mean_variance.size() != poses.size())
      return Status::Error("the coloured noise model gives a variance for another pose count");
    result->coloured_noise = coloured.white_p_value < options.alpha / 4.0;
    result->noise_note = StringPrintf(
        "%s: white noise against it p = %.3g %s alpha/4 = %.3g, so the pose means are weighted "
        "by %s",
        coloured.description.c_str(), coloured.white_p_value,
        result->coloured_noise ? "<" : ">=", options.alpha / 4.0,
        result->coloured_noise ? "it" : "white noise");
    if (result->coloured_noise) noise = coloured.pose_mean_variance;
  } else {
    result->noise_note = "white noise of the within-pose variance (no coloured model offered)";
  }
  if (result->coloured_noise) {
    ACCELCAL_RETURN_IF_ERROR(Fit(poses, options, noise, {}, &result->baseline));
  } else {
    result->baseline = result->white;
  }

  // 2. Effects: the untestable ones shown, the testable ones selected forward.
  std::vector<int> testable;
  std::vector<std::vector<int>> untestable;
  SplitCandidates(&testable, &untestable);
  for (const std::vector<int>& group : untestable) {
    const TriadEffectInfo& info = TriadEffectInfos()[coefficients[group.front()].effect];
    TriadUntestable entry;
    entry.effect = info.name;
    entry.confounded_with = info.confounded_with;
    TriadMlResult fit;
    const Status status = Fit(poses, options, noise, group, &fit);
    entry.rank_check =
        status.ok() ? "fitted: the rank check did not flag it on these poses"
                    : "not identifiable with the 9 parameters: " + JoinStrings(fit.unidentifiable);
    entry.reason = std::string("not testable from static poses: confounded with ") +
                   info.confounded_with + " (" + entry.rank_check + ")";
    result->untestable.push_back(entry);
  }

  // The one procedure's forward selection and backward elimination, and its look-alikes
  // (estimation/discovery/selection.h), over the testable coefficients.
  TriadGeometry geometry(poses, options, noise, testable, result->baseline);
  SelectionOptions selection;
  selection.alpha = options.alpha / 2.0;
  selection.max_effects = options.max_effects;
  SelectionRecord record;
  std::vector<int> candidates(testable.size());
  for (size_t c = 0; c < candidates.size(); ++c) candidates[c] = static_cast<int>(c);
  ACCELCAL_RETURN_IF_ERROR(SelectEffects(&geometry, candidates, selection, &record));
  for (const SelectionRecord::NotTested& entry : record.not_tested) {
    TriadUntestable untested;
    untested.effect = coefficients[geometry.Coefficient(entry.candidate)].name;
    untested.reason = entry.why;
    result->untestable.push_back(untested);
  }
  for (size_t i = 0; i < record.scores.size(); ++i) {
    const SelectionRecord::Score& score = record.scores[i];
    TriadCandidateScore entry;
    entry.step = score.step;
    entry.coefficient = geometry.Coefficient(score.candidate);
    entry.name = coefficients[entry.coefficient].name;
    entry.estimate = geometry.details()[i].estimate;
    entry.stddev = geometry.details()[i].stddev;
    entry.delta_chi2 = score.delta_chi2;
    entry.f = geometry.details()[i].f;
    entry.p_value = score.p_value;
    entry.significant = score.significant;
    result->candidates.push_back(entry);
  }
  geometry.SortEffects();
  const TriadMlResult current = geometry.current();
  const std::vector<int> model = geometry.Coefficients();
  result->final_fit = current;
  std::vector<CandidateTest> necessity;
  ACCELCAL_RETURN_IF_ERROR(geometry.TestEffects(&necessity));
  std::vector<double> necessary;
  for (const CandidateTest& test : necessity) necessary.push_back(test.delta_chi2);
  // 4. Ambiguity: the same model with another candidate instead of each effect.
  const std::vector<SwappedModel> swaps = FitSwaps(&geometry, candidates);
  for (const LookAlike& look_alike : FindLookAlikes(geometry, candidates, swaps, necessary)) {
    TriadAmbiguity ambiguity;
    ambiguity.effect = coefficients[model[look_alike.effect]].name;
    ambiguity.alternative = coefficients[geometry.Coefficient(look_alike.alternative)].name;
    ambiguity.delta_chi2 = look_alike.fit.worse;
    ambiguity.text =
        StringPrintf("%s and %s fit these poses about equally well (delta chi2 = %.2g)",
                     ambiguity.effect.c_str(), ambiguity.alternative.c_str(), ambiguity.delta_chi2);
    result->ambiguities.push_back(ambiguity);
  }
  // And a candidate that the data cannot tell from its absence where it matters (issue 33, item
  // 2): beside an effect found, or in the place of another, it moves the effect by
  // partner_shift_sigma or more and gains (or explains) p <= partner_alpha.
  for (const Partner& partner :
       FindPartners(&geometry, candidates, swaps, necessary,
                    PartnerOptions{options.partner_alpha, options.partner_shift_sigma,
                                   options.partner_reach_sigma})) {
    const int c = model[partner.effect];
    const std::string unit = TriadEffectUnit(c, options.unit);
    TriadAmbiguity ambiguity;
    ambiguity.effect = coefficients[c].name;
    const int other = geometry.Coefficient(partner.partner);
    ambiguity.beside = partner.replaces < 0;
    if (partner.replaces >= 0) ambiguity.replaces = coefficients[model[partner.replaces]].name;
    ambiguity.alternative = StringPrintf(
        "%s = %.3g +- %.2g %s %s, with %s = %.3g +- %.2g %s (%s: %.3g +- %.2g; moved by "
        "%.1f sigma, %s p = %.2g%s)",
        coefficients[other].name.c_str(), partner.fit.estimate, partner.fit.stddev,
        TriadEffectUnit(other, options.unit).c_str(),
        ambiguity.beside ? "beside it" : ("in " + ambiguity.replaces + "'s place").c_str(),
        coefficients[c].name.c_str(), partner.fit.estimates[partner.effect],
        partner.fit.stddevs[partner.effect], unit.c_str(),
        ambiguity.beside ? "alone" : ("with " + ambiguity.replaces).c_str(),
        partner.fit.current_estimates[partner.effect], partner.fit.current_stddevs[partner.effect],
        partner.shift_sigma, ambiguity.beside ? "gain" : "what it explains,", partner.p_value,
        ambiguity.beside
            ? StringPrintf("; one of its sigmas further, by %.1f sigma", partner.reach_sigma)
                  .c_str()
            : "");
    ambiguity.delta_chi2 = partner.delta_chi2;
    ambiguity.text = ambiguity.effect +
                     (ambiguity.beside ? " alone" : " with " + ambiguity.replaces) + ", or " +
                     ambiguity.alternative;
    result->ambiguities.push_back(ambiguity);
  }
  for (size_t e = 0; e < model.size(); ++e) {
    const int c = model[e];
    TriadFoundEffect effect;
    effect.coefficient = c;
    effect.name = coefficients[c].name;
    effect.unit = TriadEffectUnit(c, options.unit);
    effect.estimate = current.effects[c];
    effect.stddev = current.effects_stddev[c];
    for (const TriadCandidateScore& score : result->candidates)
      if (score.coefficient == c && score.significant && effect.step == 0) effect.step = score.step;
    if (necessity[e].delta_chi2 != HUGE_VAL) {
      effect.delta_chi2 = necessity[e].delta_chi2;
      effect.p_value = necessity[e].p_value;
    }
    result->effects.push_back(effect);
  }

  // 3. What remains.
  static const TriadPoseCorrelation kIndependent;
  ACCELCAL_RETURN_IF_ERROR(CheckWhatRemains(
      poses, current, noise, model,
      result->coloured_noise && !coloured.correlation.empty() ? coloured.correlation : kIndependent,
      options, options.alpha / 4.0, result));
  result->noise_overstated = CheckNoiseOverstated(current, options.alpha / 4.0);

  // 5. The gain out of sample.
  if (options.cross_validation_folds >= 2 &&
      static_cast<int>(poses.size()) >= 2 * options.cross_validation_folds) {
    TriadCrossValidation& cv = result->cross_validation;
    cv.folds = options.cross_validation_folds;
    cv.poses = static_cast<int>(poses.size());
    const std::array<double, 3> white = result->white.noise_variance;
    const Status baseline = CrossValidate(poses, options, noise, white, {}, &cv.baseline);
    if (baseline.ok() && !model.empty()) {
      if (!CrossValidate(poses, options, noise, white, model, &cv.final_model).ok()) cv.folds = 0;
    } else {
      cv.final_model = cv.baseline;
      if (!baseline.ok()) cv.folds = 0;
    }
  }

  // The verdict.
  std::string found;
  for (const TriadFoundEffect& effect : result->effects) {
    found += StringPrintf("%s%s = %.3g +- %.2g %s", found.empty() ? "" : ", ", effect.name.c_str(),
                          effect.estimate, effect.stddev, effect.unit.c_str());
  }
  if (result->coloured_noise)
    found = "coloured noise of the pose means" + (found.empty() ? "" : "; " + found);
  result->verdict_code =
      DecideVerdict(!result->remaining.empty(), !result->ambiguities.empty(), !found.empty());
  if (result->verdict_code == Verdict::kUnexplained) {
    result->verdict = "unexplained structure remains: " + JoinStrings(result->remaining, "; ");
    if (!result->explained_by_shape.empty()) {
      result->verdict += " (forward selection found " + JoinStrings(result->explained_by_shape) +
                         ", but the shape named first explains the poses better without: not "
                         "kept)";
    } else {
      result->verdict += found.empty() ? " (no effect the model knows explains it)"
                                       : " (found and kept: " + found + ")";
    }
    // What the effects found cannot be told apart from, also when structure remains.
    for (const TriadAmbiguity& a : result->ambiguities)
      result->verdict += "; cannot tell apart: " + a.text;
  } else if (result->verdict_code == Verdict::kCannotTellApart) {
    result->verdict = "cannot tell apart: " + result->ambiguities.front().text +
                      "; poses held at other times or directions would separate them (the model "
                      "as fitted: " +
                      found + ")";
  } else if (result->verdict_code == Verdict::kMissing) {
    result->verdict = "missing from the 9-parameter model, found: " + found +
                      StringPrintf("; the extended model explains the poses (chi2/dof = %.3g)",
                                   current.chi2_per_dof);
  } else {
    result->verdict = StringPrintf(
        "explained: the 9-parameter model with %s noise explains the poses (chi2/dof = %.3g on "
        "%d dof, p = %.3g)",
        result->coloured_noise ? "coloured" : "white", current.chi2_per_dof,
        current.degrees_of_freedom, current.p_value);
    // "No effect is needed" only when some candidate was tested (issue 45: said of a 10-pose
    // session with 1 degree of freedom, where none could be).
    if (!result->candidates.empty()) {
      result->verdict += "; no candidate effect is needed";
    } else {
      std::string why;
      for (const TriadUntestable& u : result->untestable)
        if (u.confounded_with.empty() && why.empty()) why = u.reason;
      result->verdict +=
          "; but no candidate effect could be tested" + (why.empty() ? "" : " (" + why + ")") +
          ", so the session cannot show whether one is missing: hold the sensor in more poses";
    }
  }
  if (result->noise_overstated.flagged)
    result->verdict += "; note: " + result->noise_overstated.description;
  return Status::Ok();
}

}  // namespace accelcal
