#include "estimation/discovery.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "common/format.h"
#include "estimation/chi_square.h"
#include "estimation/linear_ls.h"

namespace accelcal {
namespace {

double TotalChi2(const JointResult& result) {
  return result.chi2_x + result.chi2_y + result.chi2_endpoint;
}

// The landmark the current model points at, judged without tying the run to any: a
// landmark-free fit of the model, dead-reckoned, scored by Mahalanobis distance. An
// unmodelled effect can bias the baseline's endpoint toward the wrong landmark, so the
// tie is decided again each time the model grows.
Status MostProbableLandmark(const CalibrationTest& test, const VehicleRun& run,
                            const RunConditions& conditions, const std::vector<Landmark>& landmarks,
                            JointOptions options, double alpha, std::string* name) {
  name->clear();
  if (landmarks.empty()) return Status::Ok();
  options.landmark_mode = JointOptions::Landmark::kNone;
  std::vector<Parameter> calibration_effects;
  for (const Parameter effect : options.effects) {
    if (!ActsOnlyInRun(effect)) calibration_effects.push_back(effect);
  }
  options.effects = calibration_effects;
  JointResult free_run;
  ACCELCAL_RETURN_IF_ERROR(SolveJoint(test, run, conditions, landmarks, options, &free_run));
  TrajectoryOptions trajectory;
  trajectory.path_stride = run.size();
  DeadReckoningResult result;
  ACCELCAL_RETURN_IF_ERROR(DeadReckon(run, conditions, free_run.estimate, trajectory, &result));
  const LandmarkDecision decision =
      DecideLandmark(result.endpoint, result.covariance, landmarks, alpha);
  if (decision.best >= 0) *name = decision.scores[decision.best].landmark.name;
  return Status::Ok();
}

// Mean whitened squared error of held-out calibration rows when the model, linearised at
// its solution, is refitted on the other folds: exact for a linear model, and free of
// the drift coordinate's dependence on the sample's place in the whole test.
double CrossValidate(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residual,
                     int calibration_rows, int folds) {
  double error = 0.0;
  const int p = static_cast<int>(jacobian.cols());
  const int samples = calibration_rows / 2;
  for (int fold = 0; fold < folds; ++fold) {
    // Contiguous blocks of samples (both axes of a sample stay together).
    const int begin = 2 * (static_cast<long long>(samples) * fold / folds);
    const int end = 2 * (static_cast<long long>(samples) * (fold + 1) / folds);
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(p, p);
    Eigen::VectorXd gradient = Eigen::VectorXd::Zero(p);
    for (int row = 0; row < jacobian.rows(); ++row) {
      if (row >= begin && row < end) continue;
      normal.noalias() += jacobian.row(row).transpose() * jacobian.row(row);
      gradient.noalias() += jacobian.row(row).transpose() * residual[row];
    }
    const Eigen::VectorXd step = normal.ldlt().solve(gradient);
    for (int row = begin; row < end; ++row)
      error += std::pow(residual[row] - jacobian.row(row).dot(step), 2);
  }
  return error / calibration_rows;
}

std::string Fixed(double value, double stddev, const char* unit) {
  return StringPrintf("%.3g +- %.2g %s", value, stddev, unit);
}

}  // namespace

Status Discover(const CalibrationTest& test, const VehicleRun& run, const RunConditions& conditions,
                const std::vector<Landmark>& landmarks, const DiscoveryOptions& options,
                DiscoveryResult* result) {
  *result = DiscoveryResult();
  // 1. The baseline and what it leaves.
  LinearLsOptions linear;
  linear.gravity_mps2 = options.gravity_mps2;
  linear.noise_variance_x = conditions.noise_variance_x;
  linear.noise_variance_y = conditions.noise_variance_y;
  ACCELCAL_RETURN_IF_ERROR(EstimateLinearLs(test, linear, &result->baseline));
  const ParameterEstimate baseline = FromBaselineFit(result->baseline);
  std::array<std::vector<double>, 2> residuals;
  CalibrationResiduals(test, baseline.values, options.gravity_mps2, &residuals[0], &residuals[1]);
  const std::array<double, 2> stated = {conditions.noise_variance_x, conditions.noise_variance_y};
  std::vector<double> noise_p_values;
  for (int k = 0; k < 2; ++k) {
    AxisDiagnostics& axis = result->axes[k];
    axis.noise = TestNoiseLevel(residuals[k], stated[k]);
    axis.chi2 = (k == 0 ? result->baseline.chi2_x : result->baseline.chi2_y).chi2;
    axis.dof = (k == 0 ? result->baseline.chi2_x : result->baseline.chi2_y).dof;
    axis.whiteness = LjungBox(residuals[k], options.ljung_box_lags);
    axis.normality = JarqueBera(residuals[k]);
    noise_p_values.push_back(axis.noise.p_value);
  }
  // 2. Noise first. The procedure has two families of tests, the noise levels and the
  // effects; each gets alpha/2 (Holm within it), so that the whole discovery keeps its
  // family-wise error rate at alpha (Bonferroni across the two).
  const double family_alpha = 0.5 * options.alpha;
  const std::vector<bool> noise_flagged = HolmRejections(noise_p_values, family_alpha);
  for (int k = 0; k < 2; ++k) {
    AxisDiagnostics& axis = result->axes[k];
    axis.noise_flagged = noise_flagged[k];
    result->noise_variance_used[k] = stated[k] * (axis.noise_flagged ? axis.noise.ratio : 1.0);
    axis.bins = BinByTheta(test.theta_rad, residuals[k], options.theta_bins,
                           result->noise_variance_used[k]);
    if (axis.noise_flagged) {
      DiscoveredEffect effect;
      effect.effect = k == 0 ? Parameter::kNoiseVarianceX : Parameter::kNoiseVarianceY;
      effect.estimate = axis.noise.ratio;
      effect.stddev = axis.noise.ratio_stddev;
      effect.p_value = axis.noise.p_value;
      effect.delta_chi2 = axis.noise.z * axis.noise.z;
      result->effects.push_back(effect);
    }
  }
  // The endpoint against the landmarks, with the noise the data show.
  ParameterEstimate noise_scaled = baseline;
  noise_scaled.values[Parameter::kNoiseVarianceX] = result->noise_variance_used[0] / stated[0];
  noise_scaled.values[Parameter::kNoiseVarianceY] = result->noise_variance_used[1] / stated[1];
  TrajectoryOptions trajectory;
  trajectory.path_stride = run.size();
  ACCELCAL_RETURN_IF_ERROR(
      DeadReckon(run, conditions, noise_scaled, trajectory, &result->baseline_trajectory));
  result->baseline_decision =
      DecideLandmark(result->baseline_trajectory.endpoint, result->baseline_trajectory.covariance,
                     landmarks, options.alpha);
  const LandmarkDecision& decision = result->baseline_decision;
  if (decision.best >= 0) {
    result->tied_landmark = decision.scores[decision.best].landmark.name;
    std::vector<double> posteriors;
    for (const LandmarkScore& score : decision.scores) posteriors.push_back(score.posterior);
    std::sort(posteriors.rbegin(), posteriors.rend());
    const bool ambiguous = posteriors.size() > 1 && posteriors[1] > options.alpha;
    result->landmark_note =
        decision.consistent
            ? StringPrintf("the baseline endpoint is consistent with %s (p = %.3g)",
                           result->tied_landmark.c_str(), decision.scores[decision.best].p_value)
            : StringPrintf(
                  "no landmark is consistent with the baseline endpoint (the closest, %s, has p = "
                  "%.2g): "
                  "a run bias shift is tested against it",
                  result->tied_landmark.c_str(), decision.scores[decision.best].p_value);
    if (ambiguous) {
      result->landmark_note +=
          StringPrintf("; the choice is ambiguous (second posterior %.3g)", posteriors[1]);
    }
  }

  // 3. Forward selection over the catalogue.
  JointOptions joint;
  joint.gravity_mps2 = options.gravity_mps2;
  joint.noise_variance_x = result->noise_variance_used[0];
  joint.noise_variance_y = result->noise_variance_used[1];
  joint.num_threads = options.num_threads;
  joint.landmark_mode = result->tied_landmark.empty() ? JointOptions::Landmark::kNone
                                                      : JointOptions::Landmark::kNamed;
  joint.landmark_name = result->tied_landmark;
  ACCELCAL_RETURN_IF_ERROR(
      SolveJoint(test, run, conditions, landmarks, joint, &result->baseline_joint));
  JointResult current = result->baseline_joint;
  const double log_n = std::log(2.0 * test.size() + (result->tied_landmark.empty() ? 0 : 2));
  std::vector<Parameter> remaining;
  for (const ParameterInfo& info : ParameterCatalogue()) {
    if (info.baseline || IsNoiseRatio(info.parameter)) continue;
    if (ActsOnlyInRun(info.parameter) && result->tied_landmark.empty()) continue;
    remaining.push_back(info.parameter);
  }
  // Re-decides the landmark tie for the model of `joint` and refits `current` when it moves.
  auto retie = [&](const char* because) -> Status {
    if (joint.landmark_mode != JointOptions::Landmark::kNamed) return Status::Ok();
    std::string tie;
    ACCELCAL_RETURN_IF_ERROR(
        MostProbableLandmark(test, run, conditions, landmarks, joint, options.alpha, &tie));
    if (!tie.empty() && tie != joint.landmark_name) {
      result->landmark_note += StringPrintf("; %s, the run points at %s, not %s, and is tied to it",
                                            because, tie.c_str(), joint.landmark_name.c_str());
      joint.landmark_name = tie;
      result->tied_landmark = tie;
      ACCELCAL_RETURN_IF_ERROR(SolveJoint(test, run, conditions, landmarks, joint, &current));
    }
    return Status::Ok();
  };
  // The chi-square each effect of the model removes from it: the model without the effect,
  // refitted with the same tie, against the model itself. An effect the smaller model cannot
  // be solved without (it never happens for a model that was solved with it) counts as needed.
  auto necessity = [&](std::vector<double>* delta_chi2) -> Status {
    delta_chi2->assign(joint.effects.size(), HUGE_VAL);
    for (size_t e = 0; e < joint.effects.size(); ++e) {
      JointOptions smaller = joint;
      smaller.effects.erase(smaller.effects.begin() + e);
      JointResult without;
      if (SolveJoint(test, run, conditions, landmarks, smaller, &without).ok()) {
        (*delta_chi2)[e] = std::max(0.0, TotalChi2(without) - TotalChi2(current));
      }
    }
    return Status::Ok();
  };
  // An effect dropped by backward elimination is not offered again (it left `remaining` when
  // it was added), so the alternation ends.
  int step = 1;
  for (bool changed = true; changed;) {
    changed = false;
    // Forward selection over the candidates left (numbering on from the last step scored).
    if (!result->candidates.empty()) step = result->candidates.back().step + 1;
    for (; !remaining.empty() && static_cast<int>(joint.effects.size()) < options.max_effects;
         ++step) {
      std::vector<double> delta_chi2;
      ACCELCAL_RETURN_IF_ERROR(ScoreCandidates(test, run, conditions, landmarks, joint, current,
                                               remaining, &delta_chi2));
      std::vector<double> p_values;
      for (double value : delta_chi2) p_values.push_back(ChiSquareSurvival(value, 1.0));
      const std::vector<bool> significant = HolmRejections(p_values, family_alpha);
      int best = -1;
      for (size_t c = 0; c < remaining.size(); ++c) {
        result->candidates.push_back(
            {step, remaining[c], delta_chi2[c], p_values[c], significant[c]});
        if (significant[c] && (best < 0 || delta_chi2[c] > delta_chi2[best]))
          best = static_cast<int>(c);
      }
      if (best < 0) break;
      JointOptions extended = joint;
      extended.effects.push_back(remaining[best]);
      JointResult refit;
      const Status status = SolveJoint(test, run, conditions, landmarks, extended, &refit);
      if (!status.ok()) {
        // Not separable from what is already in the model: drop it and look again.
        remaining.erase(remaining.begin() + best);
        continue;
      }
      DiscoveredEffect effect;
      effect.effect = remaining[best];
      effect.selection_step = step;
      effect.selection_p_value = p_values[best];
      // Same tie before and after.
      effect.selection_delta_chi2 = TotalChi2(current) - TotalChi2(refit);
      result->effects.push_back(effect);
      result->history.push_back({SelectionEvent::Kind::kAdded, effect.effect,
                                 effect.selection_delta_chi2, effect.selection_p_value,
                                 joint.landmark_name});
      joint = extended;
      current = refit;
      remaining.erase(remaining.begin() + best);
      // The grown model may point at another landmark; tie the run to it from now on.
      if (!ActsOnlyInRun(effect.effect)) {
        ACCELCAL_RETURN_IF_ERROR(
            retie(StringPrintf("with %s in the model", Info(effect.effect).name).c_str()));
      }
    }
    // Backward elimination against the grown model.
    while (!joint.effects.empty()) {
      std::vector<double> delta_chi2;
      ACCELCAL_RETURN_IF_ERROR(necessity(&delta_chi2));
      std::vector<double> p_values;
      for (double value : delta_chi2) p_values.push_back(ChiSquareSurvival(value, 1.0));
      const std::vector<bool> needed = HolmRejections(p_values, family_alpha);
      int weakest = -1;
      for (size_t e = 0; e < joint.effects.size(); ++e) {
        if (!needed[e] && (weakest < 0 || p_values[e] > p_values[weakest]))
          weakest = static_cast<int>(e);
      }
      if (weakest < 0) break;
      const Parameter gone = joint.effects[weakest];
      result->history.push_back({SelectionEvent::Kind::kDropped, gone, delta_chi2[weakest],
                                 p_values[weakest], joint.landmark_name});
      joint.effects.erase(joint.effects.begin() + weakest);
      result->effects.erase(
          std::find_if(result->effects.begin(), result->effects.end(),
                       [&](const DiscoveredEffect& effect) { return effect.effect == gone; }));
      ACCELCAL_RETURN_IF_ERROR(SolveJoint(test, run, conditions, landmarks, joint, &current));
      ACCELCAL_RETURN_IF_ERROR(
          retie(StringPrintf("without %s in the model", Info(gone).name).c_str()));
      changed = true;
    }
  }
  // Every figure of the final model's effects against the final model itself.
  {
    std::vector<double> delta_chi2;
    ACCELCAL_RETURN_IF_ERROR(necessity(&delta_chi2));
    for (size_t e = 0; e < joint.effects.size(); ++e) {
      for (DiscoveredEffect& effect : result->effects) {
        if (effect.effect != joint.effects[e]) continue;
        effect.delta_chi2 = delta_chi2[e];
        effect.p_value = ChiSquareSurvival(delta_chi2[e], 1.0);
        effect.bic_change = -effect.delta_chi2 + log_n;
      }
    }
  }
  result->extended = current;
  for (DiscoveredEffect& effect : result->effects) {
    if (IsNoiseRatio(effect.effect)) continue;
    effect.estimate = current.estimate.Value(effect.effect);
    effect.stddev = current.estimate.StandardDeviation(effect.effect);
  }

  // 4. The gain.
  ACCELCAL_RETURN_IF_ERROR(
      DeadReckon(run, conditions, current.estimate, trajectory, &result->extended_trajectory));
  result->extended_decision =
      DecideLandmark(result->extended_trajectory.endpoint, result->extended_trajectory.covariance,
                     landmarks, options.alpha);
  std::array<std::vector<double>, 2> extended_residuals;
  CalibrationResiduals(test, current.estimate.values, options.gravity_mps2, &extended_residuals[0],
                       &extended_residuals[1]);
  for (int k = 0; k < 2; ++k) {
    std::vector<double> difference(test.size());
    for (int i = 0; i < test.size(); ++i)
      difference[i] = residuals[k][i] - extended_residuals[k][i];
    const std::vector<ResidualBin> signature =
        BinByTheta(test.theta_rad, difference, options.theta_bins, result->noise_variance_used[k]);
    for (const ResidualBin& bin : signature) result->axes[k].bin_signature.push_back(bin.mean);
  }
  if (options.cross_validation_folds > 1) {
    const int calibration_rows = 2 * test.size();
    Eigen::MatrixXd jacobian;
    Eigen::VectorXd residual;
    ACCELCAL_RETURN_IF_ERROR(
        LinearizeJoint(test, run, conditions, landmarks, joint, current, &jacobian, &residual));
    // Only the parameters the tilt test sees are refitted per fold.
    std::vector<int> columns;
    for (size_t c = 0; c < current.estimate.free.size(); ++c) {
      if (!ActsOnlyInRun(current.estimate.free[c])) columns.push_back(static_cast<int>(c));
    }
    Eigen::MatrixXd calibration(calibration_rows, columns.size());
    for (size_t c = 0; c < columns.size(); ++c)
      calibration.col(c) = jacobian.col(columns[c]).head(calibration_rows);
    result->cross_validation.folds = options.cross_validation_folds;
    result->cross_validation.extended =
        CrossValidate(calibration, residual.head(calibration_rows), calibration_rows,
                      options.cross_validation_folds);
    // The baseline's own linearisation at its own solution (no effect, same noise).
    JointOptions base = joint;
    base.effects.clear();
    ACCELCAL_RETURN_IF_ERROR(LinearizeJoint(test, run, conditions, landmarks, base,
                                            result->baseline_joint, &jacobian, &residual));
    result->cross_validation.baseline =
        CrossValidate(jacobian.topLeftCorner(calibration_rows, 4), residual.head(calibration_rows),
                      calibration_rows, options.cross_validation_folds);
  }

  // The verdict, first line of every report.
  std::string missing;
  for (const DiscoveredEffect& effect : result->effects) {
    const ParameterInfo& info = Info(effect.effect);
    missing += (missing.empty() ? "" : "; ") + std::string(info.name) + " = " +
               Fixed(effect.estimate, effect.stddev, info.unit) +
               StringPrintf(" (delta chi2 = %.1f, p = %.2g)", effect.delta_chi2, effect.p_value);
  }
  result->verdict =
      missing.empty() ? "the baseline explains the data: no effect of the catalogue is significant "
                        "at alpha = " +
                            StringPrintf("%g", options.alpha)
                      : "missing: " + missing;
  return Status::Ok();
}

}  // namespace accelcal
