#include "estimation/triad/triad_discovery.h"

#include <ceres/ceres.h>
#include <ceres/sphere_manifold.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "common/format.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/statistics/diagnostics.h"
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
  return CalibrateTriadMl(poses, fit, result);
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

// The direction of a held-out pose fitted with the parameters and effects of `fit` held;
// returns its whitened chi-square (3 residuals, 2 unknowns).
double HeldOutChi2(const TriadPoseMean& pose, const std::array<double, 3>& mean_stddev,
                   const TriadMlResult& fit, double gravity_mps2) {
  TriadParameters parameters = fit.parameters;
  TriadEffectCoefficients effects = fit.effects;
  const int first_k2 = TriadEffectCoefficientIndex("scale_nonlinearity_x");
  double force[3] = {0.0, 0.0, 0.0};
  std::array<double, 3> direction = {0.0, 0.0, 1.0};
  if (TriadSpecificForce(parameters.data(), &effects[first_k2], pose.mean.data(), force)) {
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
        stddev[k] = std::sqrt((pose_mean_variance.empty()
                                   ? white_variance[k] / poses[p].sample_count
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

// Step 3: the checks of what the final model leaves, Holm at `alpha`.
void CheckWhatRemains(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                      double alpha, TriadDiscoveryResult* result) {
  ResidualCheck chi2;
  chi2.name = "chi2";
  chi2.statistic = fit.chi2_per_dof;
  chi2.dof = fit.degrees_of_freedom;
  chi2.p_value = ChiSquareSurvival(fit.chi2, fit.degrees_of_freedom);
  chi2.description = StringPrintf(
      "the pose means scatter more than the noise model says: chi2/dof = %.3g on %d dof "
      "(expected 1 +- %.2g, p = %.3g)",
      fit.chi2_per_dof, fit.degrees_of_freedom, fit.chi2_per_dof_spread, chi2.p_value);

  // Consecutive poses in time: a self-normalised sum of products of neighbours' residuals,
  // N(0, 1) when they are independent.
  const std::vector<int> order = PosesInTimeOrder(poses);
  double products = 0.0;
  double squares = 0.0;
  double norm = 0.0;
  for (size_t i = 0; i + 1 < order.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double a = fit.whitened_residuals[order[i]][k];
      const double b = fit.whitened_residuals[order[i + 1]][k];
      products += a * b;
      squares += a * a * b * b;
    }
  }
  for (const auto& r : fit.whitened_residuals)
    for (int k = 0; k < 3; ++k) norm += r[k] * r[k];
  ResidualCheck lag;
  lag.name = "pose_lag1_correlation";
  lag.statistic = norm > 0.0 ? products / norm : 0.0;
  const double z = squares > 0.0 ? products / std::sqrt(squares) : 0.0;
  lag.p_value = std::erfc(std::abs(z) / std::sqrt(2.0));
  // What the correlation found, by its sign: alike neighbours are a slow wander; alternating
  // ones are not (something that flips between consecutive poses: the order the orientations
  // were held in, a hysteresis, an effect of the pose's direction the model lacks).
  lag.description =
      lag.statistic >= 0.0
          ? StringPrintf(
                "consecutive poses' residuals are alike: lag-1 correlation r = %+.2f (z = %.2f, "
                "p = %.3g), the offsets wander slowly from pose to pose",
                lag.statistic, z, lag.p_value)
          : StringPrintf(
                "consecutive poses' residuals alternate in sign: lag-1 correlation r = %+.2f "
                "(z = %.2f, p = %.3g), not a slow wander but something that flips from one pose "
                "to the next (the order the orientations were held in, hysteresis, or an effect "
                "of the pose's direction the model lacks)",
                lag.statistic, z, lag.p_value);

  result->checks = {chi2, lag};
  FlagByHolm(alpha, &result->checks);
  for (const ResidualCheck& check : result->checks)
    if (check.flagged) result->remaining.push_back(check.description);
  if (result->checks[0].flagged) result->pose_wander = PoseWander(fit);
}

// Step 3's other tail, beside the verdict: a chi-square too small for its degrees of freedom.
ResidualCheck CheckNoiseOverstated(const TriadMlResult& fit, double alpha) {
  ResidualCheck check;
  check.name = "chi2_lower_tail";
  check.statistic = fit.chi2_per_dof;
  check.dof = fit.degrees_of_freedom;
  check.p_value = ChiSquareCdf(fit.chi2, fit.degrees_of_freedom);
  check.flagged = check.p_value < alpha;
  check.description = StringPrintf(
      "the pose means scatter less than the noise model says: chi2/dof = %.3g on %d dof (p = "
      "%.3g in the lower tail); the noise model overstates a pose mean's variance (noise "
      "anti-correlated within a pose, or variance that averages out over a pose), so the sigmas "
      "are conservative, by a factor of about %.2g",
      fit.chi2_per_dof, fit.degrees_of_freedom, check.p_value,
      1.0 / std::sqrt(std::max(fit.chi2_per_dof, 1e-12)));
  return check;
}

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

  std::vector<int> model;
  TriadMlResult current = result->baseline;
  std::vector<int> left = testable;
  for (int step = 1; step <= options.max_effects && !left.empty(); ++step) {
    // A candidate whose fit would leave no degree of freedom, or that cannot be fitted, is
    // not tested: it is listed as not testable, with why, rather than scored 0 +- 0, p = 1.
    const int dof_left = current.degrees_of_freedom - 1;
    std::vector<TriadMlResult> fits(left.size());
    std::vector<int> tested;
    std::vector<TriadMlResult> tested_fits;
    for (size_t i = 0; i < left.size(); ++i) {
      TriadUntestable entry;
      entry.effect = coefficients[left[i]].name;
      if (dof_left < 1) {
        entry.reason = StringPrintf(
            "not testable with the degrees of freedom left: the fit with it would leave %d (%d "
            "poses, 9 parameters, %zu effects, 2 direction angles per pose), and its F test "
            "needs at least 1",
            dof_left, current.pose_count, model.size() + 1);
        result->untestable.push_back(entry);
        continue;
      }
      std::vector<int> extended = model;
      extended.push_back(left[i]);
      const Status status = Fit(poses, options, noise, extended, &fits[i]);
      if (!status.ok()) {
        entry.reason = "not testable: the fit with it fails (" + status.message() + ")";
        result->untestable.push_back(entry);
        continue;
      }
      tested.push_back(left[i]);
      tested_fits.push_back(fits[i]);
    }
    left = tested;
    if (left.empty()) break;
    std::vector<double> p_values;
    std::vector<bool> fitted(left.size(), true);
    fits = tested_fits;
    for (size_t i = 0; i < left.size(); ++i) p_values.push_back(ExtensionPValue(current, fits[i]));
    const std::vector<bool> rejected = HolmRejections(p_values, options.alpha / 2.0);
    int best = -1;
    for (size_t i = 0; i < left.size(); ++i) {
      TriadCandidateScore score;
      score.step = step;
      score.coefficient = left[i];
      score.name = coefficients[left[i]].name;
      if (fitted[i]) {
        score.estimate = fits[i].effects[left[i]];
        score.stddev = fits[i].effects_stddev[left[i]];
        score.delta_chi2 = current.chi2 - fits[i].chi2;
        score.f = score.delta_chi2 / (fits[i].chi2 / fits[i].degrees_of_freedom);
      }
      score.p_value = p_values[i];
      score.significant = rejected[i];
      result->candidates.push_back(score);
      if (rejected[i] && (best < 0 || p_values[i] < p_values[best] ||
                          (p_values[i] == p_values[best] && fits[i].chi2 < fits[best].chi2)))
        best = static_cast<int>(i);
    }
    if (best < 0) break;
    model.push_back(left[best]);
    current = fits[best];
    left.erase(left.begin() + best);
  }
  result->final_fit = current;
  std::sort(model.begin(), model.end());
  for (const int c : model) {
    TriadFoundEffect effect;
    effect.coefficient = c;
    effect.name = coefficients[c].name;
    effect.unit = TriadEffectUnit(c, options.unit);
    effect.estimate = current.effects[c];
    effect.stddev = current.effects_stddev[c];
    for (const TriadCandidateScore& score : result->candidates)
      if (score.coefficient == c && score.significant && effect.step == 0) effect.step = score.step;
    std::vector<int> without;
    for (const int other : model)
      if (other != c) without.push_back(other);
    TriadMlResult reduced;
    if (Fit(poses, options, noise, without, &reduced).ok()) {
      effect.delta_chi2 = reduced.chi2 - current.chi2;
      effect.p_value = ExtensionPValue(reduced, current);
    }
    // 4. Ambiguity: the same model with another candidate instead of this one.
    for (const int alternative : testable) {
      if (std::find(model.begin(), model.end(), alternative) != model.end()) continue;
      std::vector<int> swapped = without;
      swapped.push_back(alternative);
      TriadMlResult fit;
      if (!Fit(poses, options, noise, swapped, &fit).ok()) continue;
      const double scatter = std::max(1.0, current.chi2 / current.degrees_of_freedom);
      const double delta = fit.chi2 - current.chi2;
      if (delta < options.ambiguity_delta_chi2 * scatter)
        result->ambiguities.push_back({effect.name, coefficients[alternative].name, delta});
    }
    result->effects.push_back(effect);
  }

  // 3. What remains.
  CheckWhatRemains(poses, current, options.alpha / 4.0, result);
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
  if (!result->remaining.empty()) {
    result->verdict_code = Verdict::kUnexplained;
    result->verdict = "unexplained structure remains: " + result->remaining.front();
    if (result->pose_wander != std::array<double, 3>{}) {
      const auto& w = result->pose_wander;
      const auto& g = options.gain_mps2_per_unit;
      result->verdict += StringPrintf(
          "; a per-pose offset wander of (%.3g, %.3g, %.3g) %s = (%.2g, %.2g, %.2g) m/s^2 "
          "would account for it",
          w[0], w[1], w[2], options.unit.c_str(), w[0] * g[0], w[1] * g[1], w[2] * g[2]);
    }
    for (size_t i = 1; i < result->remaining.size(); ++i)
      result->verdict += "; " + result->remaining[i];
    result->verdict += found.empty() ? " (no effect the model knows explains it)"
                                     : " (found and kept: " + found + ")";
  } else if (!result->ambiguities.empty()) {
    result->verdict_code = Verdict::kCannotTellApart;
    const TriadAmbiguity& a = result->ambiguities.front();
    result->verdict = StringPrintf(
        "cannot tell apart: %s and %s fit these poses about equally well (delta chi2 = %.2g); "
        "poses held at other times or directions would separate them",
        a.effect.c_str(), a.alternative.c_str(), a.delta_chi2);
  } else if (!found.empty()) {
    result->verdict_code = Verdict::kMissing;
    result->verdict = "missing from the 9-parameter model, found: " + found +
                      StringPrintf("; the extended model explains the poses (chi2/dof = %.3g)",
                                   current.chi2_per_dof);
  } else {
    result->verdict_code = Verdict::kExplained;
    result->verdict = StringPrintf(
        "explained: the 9-parameter model with %s noise explains the poses (chi2/dof = %.3g on "
        "%d dof, p = %.3g); no candidate effect is needed",
        result->coloured_noise ? "coloured" : "white", current.chi2_per_dof,
        current.degrees_of_freedom, current.p_value);
  }
  if (result->noise_overstated.flagged)
    result->verdict += "; note: " + result->noise_overstated.description;
  return Status::Ok();
}

}  // namespace accelcal
