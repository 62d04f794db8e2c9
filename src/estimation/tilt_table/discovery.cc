#include "estimation/tilt_table/discovery.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "common/format.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/tilt_table/joint_data.h"
#include "estimation/tilt_table/robust_covariance.h"
#include "estimation/tilt_table/score_test.h"

namespace accelcal {

const char* NoiseFindingName(NoiseFinding::Kind kind) {
  switch (kind) {
    case NoiseFinding::Kind::kCorrelation:
      return "noise_correlation";
    case NoiseFinding::Kind::kOutliers:
      return "outliers";
    case NoiseFinding::Kind::kHeavyTails:
      return "heavy_tailed_noise";
  }
  return "noise_correlation";
}

namespace {

double TotalChi2(const JointResult& result) {
  return result.chi2_x + result.chi2_y + result.chi2_endpoint;
}

// The landmark the current model points at, judged without tying the run to any: a
// landmark-free fit of the model, dead-reckoned, scored by Mahalanobis distance. An
// unmodelled effect can bias the baseline's endpoint toward the wrong landmark, so the
// tie is decided again each time the model grows.
Status MostProbableLandmark(const JointData& data, JointOptions options, double alpha,
                            std::string* name) {
  name->clear();
  const std::vector<Landmark>& landmarks = data.landmarks();
  if (landmarks.empty()) return Status::Ok();
  options.landmark_mode = JointOptions::Landmark::kNone;
  std::vector<Parameter> calibration_effects;
  for (const Parameter effect : options.effects) {
    if (!ActsOnlyInRun(effect)) calibration_effects.push_back(effect);
  }
  options.effects = calibration_effects;
  JointResult free_run;
  ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, options, &free_run));
  TrajectoryOptions trajectory;
  trajectory.path_stride = data.run().size();
  DeadReckoningResult result;
  ACCELCAL_RETURN_IF_ERROR(
      DeadReckon(data.run(), data.conditions(), free_run.estimate, trajectory, &result));
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
  // Every fit below starts from the baseline of its noise model; each is computed once.
  const JointData data(test, run, conditions, landmarks);
  // 1. The baseline and what it leaves.
  const JointOptions stated_noise = JointOptionsFor(conditions, options.gravity_mps2);
  const BaselineFit* baseline_fit = nullptr;
  ACCELCAL_RETURN_IF_ERROR(data.Baseline(stated_noise, &baseline_fit));
  result->baseline = *baseline_fit;
  const ParameterEstimate baseline = FromBaselineFit(result->baseline);
  std::array<std::vector<double>, 2> residuals;
  CalibrationResiduals(test, baseline.values, options.gravity_mps2, &residuals[0], &residuals[1]);
  const std::array<double, 2> stated = {conditions.noise_variance_x, conditions.noise_variance_y};
  for (int k = 0; k < 2; ++k) {
    AxisDiagnostics& axis = result->axes[k];
    axis.noise = TestNoiseLevel(residuals[k], stated[k]);
    axis.chi2 = (k == 0 ? result->baseline.chi2_x : result->baseline.chi2_y).chi2;
    axis.dof = (k == 0 ? result->baseline.chi2_x : result->baseline.chi2_y).dof;
    axis.whiteness = LjungBox(residuals[k], options.ljung_box_lags);
    axis.normality = JarqueBera(residuals[k]);
  }
  // 2. Noise first, as a model: per axis its outliers, tails, level and correlation, read
  // from local differences (estimation/statistics/noise_analysis.h). The procedure has three families
  // of tests, each with Holm inside its share of alpha (Bonferroni across them, so the
  // whole discovery keeps its family-wise error rate at alpha): the noise (alpha/4), the
  // effects (alpha/2) and the checks of what the final model leaves (alpha/4).
  const double noise_alpha = 0.25 * options.alpha;
  const double family_alpha = 0.5 * options.alpha;
  const double checks_alpha = 0.25 * options.alpha;
  NoiseAnalysisOptions analysis_options;
  analysis_options.outlier_alpha = noise_alpha / 8.0;
  std::array<NoiseAnalysis, 2> first;
  for (int k = 0; k < 2; ++k)
    first[k] = AnalyzeNoise(residuals[k], stated[k], {}, false, analysis_options);
  auto family = [](const std::array<NoiseAnalysis, 2>& a) {
    return std::vector<double>{a[0].outlier_p, a[0].kurtosis_p, a[0].level_p, a[0].correlation_p,
                               a[1].outlier_p, a[1].kurtosis_p, a[1].level_p, a[1].correlation_p};
  };
  std::vector<bool> flags = HolmRejections(family(first), noise_alpha);
  std::array<bool, 2> heavy{}, outlying{};
  std::array<NoiseAnalysis, 2>& analysis = result->noise_analysis;
  for (int k = 0; k < 2; ++k) {
    heavy[k] = flags[4 * k + 1];
    outlying[k] = flags[4 * k] && !heavy[k] && !first[k].outlier_candidates.empty();
    // Outliers can hide one another (two in one neighbourhood, or a scale they inflate): look
    // again without those found, until no more are.
    for (int pass = 0; outlying[k] && pass < 5; ++pass) {
      const NoiseAnalysis again = AnalyzeNoise(residuals[k], stated[k], first[k].outlier_candidates,
                                               false, analysis_options);
      if (again.outlier_candidates.empty()) break;
      std::vector<int>& found = first[k].outlier_candidates;
      found.insert(found.end(), again.outlier_candidates.begin(), again.outlier_candidates.end());
      std::sort(found.begin(), found.end());
    }
    // Level and correlation again without the outliers, or with the sample's own moments
    // under heavy tails (a variance test with Gaussian error bars would be wrong there).
    analysis[k] = (heavy[k] || outlying[k])
                      ? AnalyzeNoise(residuals[k], stated[k],
                                     outlying[k] ? first[k].outlier_candidates : std::vector<int>(),
                                     heavy[k], analysis_options)
                      : first[k];
    analysis[k].outlier_p = first[k].outlier_p;
    analysis[k].largest_score = first[k].largest_score;
    analysis[k].outlier_candidates = first[k].outlier_candidates;
    analysis[k].excess_kurtosis = first[k].excess_kurtosis;
    analysis[k].kurtosis_z = first[k].kurtosis_z;
    analysis[k].kurtosis_p = first[k].kurtosis_p;
  }
  flags = HolmRejections(family(analysis), noise_alpha);
  const char* axis_name[2] = {"x", "y"};
  for (int k = 0; k < 2; ++k) {
    AxisDiagnostics& axis = result->axes[k];
    AxisNoise& noise = result->noise_model[k];
    const NoiseAnalysis& a = analysis[k];
    axis.noise_flagged = flags[4 * k + 2];
    const bool correlated = flags[4 * k + 3];
    noise.variance = stated[k] * (axis.noise_flagged ? a.variance_ratio : 1.0);
    noise.correlation = correlated ? a.correlation : 0.0;
    if (outlying[k]) noise.outliers = a.outlier_candidates;
    result->noise_variance_used[k] = noise.variance;
    axis.bins = BinByTheta(test.theta_rad, residuals[k], options.theta_bins, noise.variance);
    if (axis.noise_flagged) {
      DiscoveredEffect effect;
      effect.effect = k == 0 ? Parameter::kNoiseVarianceX : Parameter::kNoiseVarianceY;
      effect.estimate = a.variance_ratio;
      effect.stddev = a.variance_ratio_stddev;
      effect.p_value = a.level_p;
      effect.delta_chi2 = a.level_z * a.level_z;
      result->effects.push_back(effect);
    }
    if (correlated) {
      NoiseFinding finding;
      finding.kind = NoiseFinding::Kind::kCorrelation;
      finding.axis = k;
      finding.estimate = a.correlation;
      finding.stddev = a.correlation_stddev;
      finding.p_value = a.correlation_p;
      finding.description = StringPrintf(
          "%s: time-correlated noise, AR(1) with lag-1 correlation %.3g +- %.2g (p = %.2g); "
          "marginal variance %.3g of the stated",
          axis_name[k], a.correlation, a.correlation_stddev, a.correlation_p, a.variance_ratio);
      result->noise_findings.push_back(finding);
    }
    if (outlying[k]) {
      NoiseFinding finding;
      finding.kind = NoiseFinding::Kind::kOutliers;
      finding.axis = k;
      finding.estimate = static_cast<double>(noise.outliers.size());
      finding.p_value = a.outlier_p;
      finding.samples = noise.outliers;
      std::string listed;
      for (size_t i = 0; i < noise.outliers.size() && i < 8; ++i)
        listed += (i ? ", " : "") + std::to_string(noise.outliers[i]);
      if (noise.outliers.size() > 8) listed += ", ...";
      finding.description = StringPrintf(
          "%s: outliers, %zu samples set aside (largest %.1f robust sigma, p = %.2g; samples %s)",
          axis_name[k], noise.outliers.size(), a.largest_score, a.outlier_p, listed.c_str());
      result->noise_findings.push_back(finding);
    }
    if (heavy[k]) {
      NoiseFinding finding;
      finding.kind = NoiseFinding::Kind::kHeavyTails;
      finding.axis = k;
      finding.estimate = a.excess_kurtosis;
      finding.p_value = a.kurtosis_p;
      finding.description = StringPrintf(
          "%s: heavy-tailed noise, excess kurtosis %.3g (p = %.2g; %zu samples beyond %.1f "
          "robust sigma); the level's spread is the sample's own",
          axis_name[k], a.excess_kurtosis, a.kurtosis_p, a.outlier_candidates.size(),
          TwoSidedNormalQuantile(analysis_options.outlier_alpha / std::max(1, a.samples)));
      result->noise_findings.push_back(finding);
    }
  }
  // The endpoint against the landmarks, with the noise the data show. With outliers or
  // correlated noise the baseline is refitted under that noise model first: least squares
  // over every sample would carry the outliers into the bias, and the run to a wrong
  // landmark, and would understate its covariance under correlation.
  ParameterEstimate noise_scaled = baseline;
  const bool structured =
      !result->noise_model[0].outliers.empty() || !result->noise_model[1].outliers.empty() ||
      result->noise_model[0].correlation != 0.0 || result->noise_model[1].correlation != 0.0;
  if (structured) {
    JointOptions refit;
    refit.gravity_mps2 = options.gravity_mps2;
    refit.noise_variance_x = result->noise_variance_used[0];
    refit.noise_variance_y = result->noise_variance_used[1];
    refit.noise_correlation = {result->noise_model[0].correlation,
                               result->noise_model[1].correlation};
    refit.outliers = {result->noise_model[0].outliers, result->noise_model[1].outliers};
    refit.num_threads = options.num_threads;
    JointResult fit;
    ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, refit, &fit));
    noise_scaled = fit.estimate;
  }
  noise_scaled.values[Parameter::kNoiseVarianceX] = result->noise_variance_used[0] / stated[0];
  noise_scaled.values[Parameter::kNoiseVarianceY] = result->noise_variance_used[1] / stated[1];
  noise_scaled.noise_correlation = {result->noise_model[0].correlation,
                                    result->noise_model[1].correlation};
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
  joint.noise_correlation = noise_scaled.noise_correlation;
  joint.outliers = {result->noise_model[0].outliers, result->noise_model[1].outliers};
  joint.num_threads = options.num_threads;
  joint.landmark_mode = result->tied_landmark.empty() ? JointOptions::Landmark::kNone
                                                      : JointOptions::Landmark::kNamed;
  joint.landmark_name = result->tied_landmark;
  ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, joint, &result->baseline_joint));
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
    ACCELCAL_RETURN_IF_ERROR(MostProbableLandmark(data, joint, options.alpha, &tie));
    if (!tie.empty() && tie != joint.landmark_name) {
      result->landmark_note += StringPrintf("; %s, the run points at %s, not %s, and is tied to it",
                                            because, tie.c_str(), joint.landmark_name.c_str());
      joint.landmark_name = tie;
      result->tied_landmark = tie;
      ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, joint, &current));
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
      if (SolveJoint(data, smaller, &without).ok()) {
        (*delta_chi2)[e] = std::max(0.0, TotalChi2(without) - TotalChi2(current));
      }
    }
    return Status::Ok();
  };
  // Drops the least significant effect of the model that Holm (alpha/2 over the model's
  // effects) does not find needed, given each effect's delta chi2 and p-value, refits and
  // re-decides the landmark tie; *dropped says whether there was one.
  auto drop_weakest = [&](const std::vector<double>& delta_chi2,
                          const std::vector<double>& p_values, SelectionEvent::Kind kind,
                          bool* dropped) -> Status {
    *dropped = false;
    const std::vector<bool> needed = HolmRejections(p_values, family_alpha);
    int weakest = -1;
    for (size_t e = 0; e < joint.effects.size(); ++e) {
      if (!needed[e] && (weakest < 0 || p_values[e] > p_values[weakest]))
        weakest = static_cast<int>(e);
    }
    if (weakest < 0) return Status::Ok();
    const Parameter gone = joint.effects[weakest];
    result->history.push_back(
        {kind, gone, delta_chi2[weakest], p_values[weakest], joint.landmark_name});
    joint.effects.erase(joint.effects.begin() + weakest);
    result->effects.erase(
        std::find_if(result->effects.begin(), result->effects.end(),
                     [&](const DiscoveredEffect& effect) { return effect.effect == gone; }));
    ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, joint, &current));
    ACCELCAL_RETURN_IF_ERROR(
        retie(StringPrintf("without %s in the model", Info(gone).name).c_str()));
    *dropped = true;
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
      ACCELCAL_RETURN_IF_ERROR(ScoreCandidates(data, joint, current, remaining, &delta_chi2));
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
      const Status status = SolveJoint(data, extended, &refit);
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
      bool dropped = false;
      ACCELCAL_RETURN_IF_ERROR(
          drop_weakest(delta_chi2, p_values, SelectionEvent::Kind::kDropped, &dropped));
      if (!dropped) break;
      changed = true;
    }
  }
  // 5. What the final model leaves (estimation/tilt_table/residual_checks.h), Holm within the checks'
  // share of alpha. A shape they find is outside the catalogue; an effect named only
  // because it resembles that shape is not needed once the shape is allowed for, so each
  // effect is tested again with the shapes as nuisance columns and the weakest one not
  // needed is dropped, until every effect left is needed.
  ResidualChecksOptions check_options;
  check_options.max_harmonic = options.max_harmonic;
  check_options.ljung_box_lags = options.ljung_box_lags;
  const AxisNoise final_noise[2] = {joint.Noise(0), joint.Noise(1)};
  Eigen::MatrixXd jacobian;
  Eigen::VectorXd linear_residual;
  auto run_checks = [&]() -> Status {
    ACCELCAL_RETURN_IF_ERROR(LinearizeJoint(data, joint, current, &jacobian, &linear_residual));
    result->checks = CheckResiduals(test, jacobian, linear_residual,
                                    current.landmark.empty() ? 0 : 2, final_noise, check_options);
    FlagByHolm(checks_alpha, &result->checks);
    return Status::Ok();
  };
  // A step can be mimicked by several catalogue effects at once (a run bias shift, a drift
  // and an angle offset together), after which the final model's checks see nothing. When
  // a single step on the baseline (its size and place: two parameters) explains at least as
  // much as all the named effects do, by BIC, the step is the simpler account: it joins the
  // nuisance shapes. A true effect explains more than any step resembling it, so it stays.
  std::vector<std::pair<int, std::vector<double>>> simpler_steps;
  if (!joint.effects.empty()) {
    JointOptions base = joint;
    base.effects.clear();
    Eigen::MatrixXd base_jacobian;
    Eigen::VectorXd base_residual;
    ACCELCAL_RETURN_IF_ERROR(
        LinearizeJoint(data, base, result->baseline_joint, &base_jacobian, &base_residual));
    const double effects_gain = TotalChi2(result->baseline_joint) - TotalChi2(current);
    const double effects_bic = effects_gain - joint.effects.size() * log_n;
    for (const ResidualCheck& check : CheckResiduals(
             test, base_jacobian, base_residual, result->baseline_joint.landmark.empty() ? 0 : 2,
             final_noise, check_options)) {
      if (check.name.find("step") == std::string::npos) continue;
      if (check.statistic - 2.0 * log_n >= effects_bic && check.p_value <= checks_alpha)
        simpler_steps.push_back({check.axis, check.shape[0]});
    }
  }
  ACCELCAL_RETURN_IF_ERROR(run_checks());
  while (!joint.effects.empty()) {
    std::vector<Eigen::VectorXd> nuisance;
    for (const ResidualCheck& check : result->checks) {
      if (!check.flagged) continue;
      for (const std::vector<double>& shape : check.shape)
        nuisance.push_back(WhitenedShapeColumn(shape, check.axis, final_noise[check.axis],
                                               static_cast<int>(jacobian.rows())));
    }
    for (const auto& [axis, shape] : simpler_steps) {
      nuisance.push_back(
          WhitenedShapeColumn(shape, axis, final_noise[axis], static_cast<int>(jacobian.rows())));
    }
    if (nuisance.empty()) break;
    // Columns of the current free parameters, by name.
    const std::vector<Parameter>& free = current.estimate.free;
    std::vector<double> p_values;
    std::vector<double> delta_chi2;
    for (const Parameter effect : joint.effects) {
      Eigen::MatrixXd others(jacobian.rows(),
                             static_cast<Eigen::Index>(free.size() - 1 + nuisance.size()));
      Eigen::MatrixXd own(jacobian.rows(), 1);
      int column = 0;
      for (size_t c = 0; c < free.size(); ++c) {
        if (free[c] == effect) {
          own.col(0) = jacobian.col(c);
        } else {
          others.col(column++) = jacobian.col(c);
        }
      }
      for (const Eigen::VectorXd& shape : nuisance) others.col(column++) = shape;
      delta_chi2.push_back(ExtraChiSquare(others, own, linear_residual));
      p_values.push_back(ChiSquareSurvival(delta_chi2.back(), 1.0));
    }
    bool dropped = false;
    ACCELCAL_RETURN_IF_ERROR(
        drop_weakest(delta_chi2, p_values, SelectionEvent::Kind::kDroppedForShape, &dropped));
    if (!dropped) break;
    ACCELCAL_RETURN_IF_ERROR(run_checks());
  }
  // What remains, in words: the flagged shapes strongest first, each kept only if it still
  // stands once the shapes before it are allowed for (a 2-theta harmonic also shows as a
  // curved trend and a step; those are parts of the same shape, not more of them).
  {
    std::vector<const ResidualCheck*> flagged;
    for (const ResidualCheck& check : result->checks) {
      if (check.flagged) flagged.push_back(&check);
    }
    std::sort(flagged.begin(), flagged.end(), [](const ResidualCheck* a, const ResidualCheck* b) {
      return a->p_value < b->p_value;
    });
    std::vector<Eigen::VectorXd> kept;
    std::string parts;
    for (const ResidualCheck* check : flagged) {
      if (check->shape.empty()) {
        result->remaining.push_back(check->description);
        continue;
      }
      Eigen::MatrixXd extra(jacobian.rows(), check->shape.size());
      for (size_t c = 0; c < check->shape.size(); ++c)
        extra.col(c) = WhitenedShapeColumn(check->shape[c], check->axis, final_noise[check->axis],
                                           static_cast<int>(jacobian.rows()));
      Eigen::MatrixXd model(jacobian.rows(), jacobian.cols() + static_cast<int>(kept.size()));
      model.leftCols(jacobian.cols()) = jacobian;
      for (size_t c = 0; c < kept.size(); ++c) model.col(jacobian.cols() + c) = kept[c];
      int rank = 0;
      const double delta = ExtraChiSquare(model, extra, linear_residual, &rank);
      const bool stands =
          kept.empty() ||
          (rank > 0 && ChiSquareSurvival(delta, rank) <=
                           checks_alpha / std::max<size_t>(1, result->checks.size()));
      if (!stands) {
        parts += (parts.empty() ? "" : ", ") + check->name;
        continue;
      }
      result->remaining.push_back(check->description);
      for (int c = 0; c < extra.cols(); ++c) kept.push_back(extra.col(c));
    }
    if (!parts.empty()) {
      result->remaining.push_back("also flagged, but parts of the shapes above: " + parts);
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
  // Heavy tails: the final model again with a Huber loss (1.345 sigma: 95% of least squares'
  // efficiency under Gaussian noise, far better under heavy tails), and the sandwich
  // covariance, right whatever the tails.
  if (std::any_of(result->noise_findings.begin(), result->noise_findings.end(),
                  [](const NoiseFinding& finding) {
                    return finding.kind == NoiseFinding::Kind::kHeavyTails;
                  })) {
    JointOptions robust = joint;
    robust.loss = RobustLoss::kHuber;
    robust.loss_scale = 1.345;
    robust.compress_calibration = false;
    JointResult fit;
    ACCELCAL_RETURN_IF_ERROR(SolveJoint(data, robust, &fit));
    ACCELCAL_RETURN_IF_ERROR(HuberSandwichCovariance(data, robust, &fit));
    current = fit;
    result->robust_fit = true;
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
    ACCELCAL_RETURN_IF_ERROR(LinearizeJoint(data, joint, current, &jacobian, &residual));
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
    const double rows =
        joint.Noise(0).InlierCount(test.size()) + joint.Noise(1).InlierCount(test.size());
    CrossValidation& cv = result->cross_validation;
    cv.null_mean = 1.0 + columns.size() / (rows * (1.0 - 1.0 / options.cross_validation_folds));
    cv.null_stddev = std::sqrt(2.0 / rows);
    // Held-out outlier rows are zero and count in the mean; compare like with like.
    cv.extended *= calibration_rows / rows;
    cv.z = (cv.extended - cv.null_mean) / cv.null_stddev;
    // The baseline's own linearisation at its own solution (no effect, same noise).
    JointOptions base = joint;
    base.effects.clear();
    ACCELCAL_RETURN_IF_ERROR(
        LinearizeJoint(data, base, result->baseline_joint, &jacobian, &residual));
    result->cross_validation.baseline =
        CrossValidate(jacobian.topLeftCorner(calibration_rows, 4), residual.head(calibration_rows),
                      calibration_rows, options.cross_validation_folds);
  }

  // 6. Effects another candidate would replace at about the same fit.
  {
    std::vector<double> necessary;
    ACCELCAL_RETURN_IF_ERROR(necessity(&necessary));
    std::vector<Parameter> candidates;
    for (const ParameterInfo& info : ParameterCatalogue()) {
      if (info.baseline || IsNoiseRatio(info.parameter)) continue;
      if (ActsOnlyInRun(info.parameter) && joint.landmark_mode != JointOptions::Landmark::kNamed)
        continue;
      if (std::find(joint.effects.begin(), joint.effects.end(), info.parameter) !=
          joint.effects.end())
        continue;
      candidates.push_back(info.parameter);
    }
    for (size_t e = 0; e < joint.effects.size(); ++e) {
      Ambiguity ambiguity;
      ambiguity.effect = joint.effects[e];
      ambiguity.effect_estimate = current.estimate.Value(ambiguity.effect);
      ambiguity.effect_stddev = current.estimate.StandardDeviation(ambiguity.effect);
      for (const Parameter candidate : candidates) {
        JointOptions swapped = joint;
        swapped.effects[e] = candidate;
        JointResult alternative;
        if (!SolveJoint(data, swapped, &alternative).ok()) continue;
        const double worse = TotalChi2(alternative) - TotalChi2(current);
        // It must explain, alone, what the effect explains (significantly), and about as well.
        const double explained = necessary[e] - worse;
        if (!(worse < options.ambiguity_delta_chi2)) continue;
        if (!(ChiSquareSurvival(explained, 1.0) <= family_alpha / candidates.size())) continue;
        ambiguity.alternatives.push_back({candidate, alternative.estimate.Value(candidate),
                                          alternative.estimate.StandardDeviation(candidate), worse,
                                          ""});
      }
      // Shapes outside the catalogue in its place: a theta harmonic on either axis that fits
      // about as well, alone explains what the effect explains, and is not merely a
      // generalisation of it (over half a circle, a 3-theta harmonic on x and
      // scale_nonlinearity_x are nearly the same shape; over a full circle, a 2-theta
      // harmonic contains scale_nonlinearity_x and is not an alternative to it). Linearised
      // at the final solution: without the effect, the residual is r + J_e (neutral - value).
      const std::vector<Parameter>& free = current.estimate.free;
      const auto column = std::find(free.begin(), free.end(), ambiguity.effect);
      if (column != free.end() && jacobian.cols() == static_cast<Eigen::Index>(free.size())) {
        const int e_col = static_cast<int>(column - free.begin());
        const Eigen::VectorXd j_e = jacobian.col(e_col);
        Eigen::MatrixXd others(jacobian.rows(), jacobian.cols() - 1);
        for (int c = 0, o = 0; c < jacobian.cols(); ++c) {
          if (c != e_col) others.col(o++) = jacobian.col(c);
        }
        const Eigen::VectorXd without =
            linear_residual +
            j_e * (Info(ambiguity.effect).neutral - current.estimate.Value(ambiguity.effect));
        // The effect's signature in the test (a harmonic can only stand for that part).
        Eigen::VectorXd test_signature = j_e;
        test_signature.tail(jacobian.rows() - 2 * test.size()).setZero();
        Eigen::MatrixXd others_in_test = others;
        others_in_test.bottomRows(jacobian.rows() - 2 * test.size()).setZero();
        const double own = ExtraChiSquare(others_in_test, test_signature, test_signature);
        for (int axis = 0; axis < 2; ++axis) {
          for (int k = 1; k <= options.max_harmonic; ++k) {
            std::vector<double> cosine(test.size()), sine(test.size());
            for (int i = 0; i < test.size(); ++i) {
              cosine[i] = std::cos(k * test.theta_rad[i]);
              sine[i] = std::sin(k * test.theta_rad[i]);
            }
            Eigen::MatrixXd shape(jacobian.rows(), 2);
            shape.col(0) = WhitenedShapeColumn(cosine, axis, final_noise[axis],
                                               static_cast<int>(jacobian.rows()));
            shape.col(1) = WhitenedShapeColumn(sine, axis, final_noise[axis],
                                               static_cast<int>(jacobian.rows()));
            Eigen::MatrixXd swapped(jacobian.rows(), others.cols() + 2);
            swapped << others, shape;
            // The harmonic must not contain the effect's own signature.
            // (in the test's rows: the run's rows of the others would hide it there)
            Eigen::MatrixXd swapped_in_test = swapped;
            swapped_in_test.bottomRows(jacobian.rows() - 2 * test.size()).setZero();
            if (!(own > 0.0) ||
                ExtraChiSquare(swapped_in_test, test_signature, test_signature) < 0.01 * own)
              continue;
            int rank = 0;
            const double gain = ExtraChiSquare(others, shape, without, &rank);
            if (rank < 1) continue;
            const double worse = necessary[e] - gain;  // its chi-square over the final model's
            if (!(worse < options.ambiguity_delta_chi2)) continue;
            if (!(ChiSquareSurvival(gain, rank) <= family_alpha / candidates.size())) continue;
            // Its amplitude in that model.
            const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> fit(swapped);
            const Eigen::VectorXd beta = fit.solve(without);
            Ambiguity::Alternative alternative;
            alternative.shape = StringPrintf("%s: %d-theta harmonic", axis == 0 ? "x" : "y", k);
            alternative.estimate = std::hypot(beta[beta.size() - 2], beta[beta.size() - 1]);
            // Its spread: the harmonic's two coefficients' (whitened rows: unit noise).
            const Eigen::MatrixXd information = swapped.transpose() * swapped;
            const Eigen::MatrixXd covariance =
                information.completeOrthogonalDecomposition().pseudoInverse();
            const Eigen::Index last = covariance.rows() - 1;
            alternative.stddev = std::sqrt(
                0.5 * std::max(0.0, covariance(last, last) + covariance(last - 1, last - 1)));
            alternative.delta_chi2 = worse;
            ambiguity.alternatives.push_back(alternative);
          }
        }
      }
      if (ambiguity.alternatives.empty()) continue;
      // What would separate them: the run, where one acts in it and another does not; else
      // more samples (the chi-square between the two models grows with them), unless this
      // design cannot separate them at any size.
      std::string separation;
      for (const Ambiguity::Alternative& alternative : ambiguity.alternatives) {
        const bool run_effect = EffectOf(ambiguity.effect).acts_in != ActsIn::kCalibrationTest;
        if (!alternative.shape.empty()) {
          // A shape acts only in the test (it was seen there); the run separates them when
          // the effect acts in it.
          const std::string line = StringPrintf(
              "%s%s, a shape outside the catalogue, fits as well as %s: this design cannot say "
              "which; a test over a full circle of theta or more positions, where their "
              "signatures differ, would",
              run_effect ? "the run, if tied to a well-known landmark, may separate them; " : "",
              alternative.shape.c_str(), Info(ambiguity.effect).name);
          separation += (separation.empty() ? "" : "; ") + line;
          continue;
        }
        const bool run_alternative =
            EffectOf(alternative.effect).acts_in != ActsIn::kCalibrationTest;
        std::string line;
        if (run_effect != run_alternative) {
          line = StringPrintf(
              "the run separates %s from %s (only %s acts in it): tie the run "
              "to a landmark whose position is known well",
              Info(ambiguity.effect).name, Info(alternative.effect).name,
              Info(run_effect ? ambiguity.effect : alternative.effect).name);
        }
        const double gap = std::abs(alternative.delta_chi2);
        const double factor = 9.2 / std::max(gap, 1e-3);
        const std::string more =
            factor > 1e4 ? StringPrintf(
                               "this test design cannot separate %s from %s at any "
                               "size: another range of theta or other positions",
                               Info(ambiguity.effect).name, Info(alternative.effect).name)
                         : StringPrintf(
                               "about %.3g times more samples of this design (their "
                               "chi-squares differ by %.2g; a likelihood ratio of 100 "
                               "needs 9.2), or a design where their signatures differ",
                               std::max(1.0, factor), gap);
        line += (line.empty() ? "" : "; or ") + more;
        separation += (separation.empty() ? "" : "; ") + line;
      }
      ambiguity.separation = separation;
      result->ambiguities.push_back(std::move(ambiguity));
    }
  }
  for (int k = 0; k < 2; ++k) result->final_residuals[k] = extended_residuals[k];
  result->noise_model = {joint.Noise(0), joint.Noise(1)};

  // The verdict, first line of every report.
  std::string missing;
  for (const DiscoveredEffect& effect : result->effects) {
    const ParameterInfo& info = Info(effect.effect);
    missing += (missing.empty() ? "" : "; ") + std::string(info.name) + " = " +
               Fixed(effect.estimate, effect.stddev, info.unit) +
               StringPrintf(" (delta chi2 = %.1f, p = %.2g)", effect.delta_chi2, effect.p_value);
  }
  for (const NoiseFinding& finding : result->noise_findings)
    missing += (missing.empty() ? "" : "; ") + finding.description;
  std::string left;
  for (const std::string& line : result->remaining) left += (left.empty() ? "" : "; ") + line;
  if (!left.empty()) {
    result->verdict_code = Verdict::kUnexplained;
    result->verdict = (missing.empty() ? std::string("unexplained: structure remains")
                                       : "missing: " + missing + ", but structure remains") +
                      " that no effect of the catalogue explains: " + left;
  } else if (!result->ambiguities.empty()) {
    result->verdict_code = Verdict::kCannotTellApart;
    std::string sets;
    for (const Ambiguity& ambiguity : result->ambiguities) {
      sets +=
          (sets.empty() ? "" : "; ") + std::string(Info(ambiguity.effect).name) + " = " +
          Fixed(ambiguity.effect_estimate, ambiguity.effect_stddev, Info(ambiguity.effect).unit);
      for (const Ambiguity::Alternative& alternative : ambiguity.alternatives) {
        sets += StringPrintf(
            " or %s = %s (delta chi2 %+.2g)", alternative.Name().c_str(),
            Fixed(alternative.estimate, alternative.stddev, alternative.Unit().c_str()).c_str(),
            alternative.delta_chi2);
      }
      sets += "; what would separate them: " + ambiguity.separation;
    }
    result->verdict = "cannot tell apart: " + sets + " (the model as fitted: " + missing + ")";
  } else if (!missing.empty()) {
    result->verdict_code = Verdict::kMissing;
    result->verdict = "missing: " + missing + " (and the extended model explains the data)";
  } else {
    result->verdict_code = Verdict::kExplained;
    result->verdict =
        "the baseline explains the data: no effect of the catalogue is significant at alpha = " +
        StringPrintf("%g", options.alpha) + ", and nothing remains that the checks can see";
  }
  return Status::Ok();
}

}  // namespace accelcal
