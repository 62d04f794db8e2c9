#include "estimation/gyroscope/gyroscope_discovery.h"

#include <algorithm>
#include <cmath>

#include "common/format.h"
#include "estimation/gyroscope/gyroscope_determination.h"
#include "estimation/statistics/chi_square.h"

namespace accelcal {
namespace {

// The iterations a fit with effects may take: it starts from the baseline's solution with the
// effects at 0, and some converge slowly (a time offset on hand-held turns: on the mimu4444
// sessions 100 iterations did not reach the tolerances in 7 of 24, 1000 do).
constexpr int kEffectFitIterations = 1000;

// A fit with a candidate whose sigma of one of the 12 unknowns is this many times the model's
// without it: the session cannot determine the candidate beside them (a session turned about one
// axis and a scale term of another: the gain and the term trade), so it is not testable there.
constexpr double kUndeterminedFactor = 100.0;

// "" when `with` determines the 12 unknowns about as `without` does; else what it leaves
// undetermined, in words.
std::string LeftUndetermined(const GyroscopeMlResult& with, const GyroscopeMlResult& without) {
  for (int i = 0;
       i < kGyroscopeCalibrationCount && i < with.stddev.size() && i < without.stddev.size(); ++i) {
    if (with.stddev[i] > kUndeterminedFactor * without.stddev[i]) {
      return StringPrintf(
          "not testable: with it the session no longer determines %s (sigma %.3g against %.3g "
          "without it)",
          with.names[i].c_str(), with.stddev[i], without.stddev[i]);
    }
  }
  return "";
}

// The fits discovery makes: the session, the accelerometer's fit, the fit options with the noise
// model fixed, and a set of effect groups (indices into GyroscopeEffectInfos()).
class GyroscopeFitter {
 public:
  GyroscopeFitter(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                  const TriadMlOptions& accelerometer_options, const TriadMlResult& accelerometer,
                  const GyroscopeMlOptions& options)
      : log_(log),
        intervals_(intervals),
        accelerometer_options_(accelerometer_options),
        accelerometer_(accelerometer),
        options_(options) {}

  Status Fit(const std::vector<int>& groups, GyroscopeMlResult* result) const {
    GyroscopeMlOptions options = options_;
    options.solve.max_iterations = std::max(options.solve.max_iterations, kEffectFitIterations);
    options.effects.clear();
    for (int group : groups) {
      const int first = GyroscopeEffectFirst(group);
      for (int c = first; c < first + GyroscopeEffectInfos()[group].coefficients; ++c)
        options.effects.push_back(c);
    }
    return CalibrateGyroscopeMl(log_, intervals_, accelerometer_options_, accelerometer_, options,
                                result);
  }

 private:
  const TriadLog& log_;
  const std::vector<StaticInterval>& intervals_;
  const TriadMlOptions& accelerometer_options_;
  const TriadMlResult& accelerometer_;
  const GyroscopeMlOptions options_;
};

class GyroscopeGeometry : public DiscoveryGeometry {
 public:
  GyroscopeGeometry(const GyroscopeFitter& fitter, const GyroscopeMlResult& baseline,
                    double ambiguity_delta_chi2)
      : fitter_(fitter), current_(baseline), ambiguity_delta_chi2_(ambiguity_delta_chi2) {}

  const GyroscopeMlResult& current() const { return current_; }

  Status TestCandidates(const std::vector<int>& candidates,
                        std::vector<CandidateTest>* tests) override {
    tests->assign(candidates.size(), CandidateTest());
    fits_.assign(candidates.size(), GyroscopeMlResult());
    tested_ = candidates;
    for (size_t i = 0; i < candidates.size(); ++i) {
      CandidateTest& test = (*tests)[i];
      std::vector<int> extended = model_;
      extended.push_back(candidates[i]);
      const Status status = fitter_.Fit(extended, &fits_[i]);
      if (!status.ok()) {
        test.tested = false;
        test.not_tested = "not testable: the fit with it fails (" + status.message() + ")";
        continue;
      }
      const std::string undetermined = LeftUndetermined(fits_[i], current_);
      if (!undetermined.empty()) {
        test.tested = false;
        test.not_tested = undetermined;
        continue;
      }
      test.delta_chi2 = std::max(0.0, current_.chi2 - fits_[i].chi2);
      test.p_value =
          ChiSquareSurvival(test.delta_chi2, GyroscopeEffectInfos()[candidates[i]].coefficients);
    }
    return Status::Ok();
  }

  Status Add(int candidate, double* delta_chi2) override {
    const auto at = std::find(tested_.begin(), tested_.end(), candidate);
    if (at == tested_.end()) return Status::Error("a candidate not tested");
    const GyroscopeMlResult& fit = fits_[at - tested_.begin()];
    *delta_chi2 = current_.chi2 - fit.chi2;
    current_ = fit;
    model_.push_back(candidate);
    return Status::Ok();
  }

  Status TestEffects(std::vector<CandidateTest>* tests) override {
    tests->assign(model_.size(), {true, HUGE_VAL, 0.0, ""});
    for (size_t e = 0; e < model_.size(); ++e) {
      GyroscopeMlResult reduced;
      if (fitter_.Fit(Without(e), &reduced).ok()) {
        (*tests)[e].delta_chi2 = std::max(0.0, reduced.chi2 - current_.chi2);
        (*tests)[e].p_value = ChiSquareSurvival((*tests)[e].delta_chi2,
                                                GyroscopeEffectInfos()[model_[e]].coefficients);
      }
    }
    return Status::Ok();
  }

  Status Drop(size_t effect) override {
    GyroscopeMlResult reduced;
    ACCELCAL_RETURN_IF_ERROR(fitter_.Fit(Without(effect), &reduced));
    current_ = reduced;
    model_.erase(model_.begin() + effect);
    return Status::Ok();
  }

  const std::vector<int>& Effects() const override { return model_; }

  bool Swap(size_t effect, int candidate, SwapFit* swap) override {
    std::vector<int> swapped = Without(effect);
    swapped.push_back(candidate);
    GyroscopeMlResult fit;
    if (!fitter_.Fit(swapped, &fit).ok() || !LeftUndetermined(fit, current_).empty()) return false;
    swap->worse = fit.chi2 - current_.chi2;
    return true;
  }

  // Within ambiguity_delta_chi2 in units of the residual scatter.
  bool FitsAboutAsWell(const SwapFit& swap) const override {
    const double scatter = std::max(1.0, current_.chi2 / current_.degrees_of_freedom);
    return swap.worse < ambiguity_delta_chi2_ * scatter;
  }

  bool LooksAlike(size_t, const SwapFit& swap, double, size_t) const override {
    return FitsAboutAsWell(swap);
  }

 private:
  std::vector<int> Without(size_t effect) const {
    std::vector<int> without;
    for (size_t e = 0; e < model_.size(); ++e)
      if (e != effect) without.push_back(model_[e]);
    return without;
  }

  const GyroscopeFitter& fitter_;
  GyroscopeMlResult current_;
  double ambiguity_delta_chi2_;
  std::vector<int> model_;
  std::vector<int> tested_;
  std::vector<GyroscopeMlResult> fits_;
};

// A chi-square's upper tail as a check.
ResidualCheck ChiSquareCheck(const std::string& name, double chi2, int dof,
                             const std::string& what) {
  ResidualCheck check;
  check.name = name;
  check.statistic = chi2;
  check.dof = dof;
  check.p_value = ChiSquareSurvival(chi2, dof);
  check.description =
      StringPrintf("%s: chi2 %.1f on %d (chi2/dof %.2f)", what.c_str(), chi2, dof, chi2 / dof);
  return check;
}

// Average ranks (1 .. n; ties share the mean of their places).
std::vector<double> Ranks(const std::vector<double>& values) {
  const size_t n = values.size();
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(n);
  for (size_t i = 0; i < n;) {
    size_t j = i;
    while (j + 1 < n && values[order[j + 1]] == values[order[i]]) ++j;
    const double rank = 0.5 * static_cast<double>(i + j) + 1.0;
    for (size_t k = i; k <= j; ++k) ranks[order[k]] = rank;
    i = j + 1;
  }
  return ranks;
}

// The turns' shapes (issue 44, item 5): does the size of the turns' whitened residuals follow a
// property of the turn? Per turn q_t = |z_t|^2 / 2 (z_t its two whitened components), per
// property g_t; Spearman's rank correlation rho of q and g over the n turns, (n - 1) rho^2 against
// chi2_1 (its variance under independence is 1 / (n - 1)), whatever the noise model's overall
// scale (which the turns' chi-square checks). Ranks, because q is exponential under the model and
// a property may have a turn far from the others: the correlation of the values themselves
// (Koenker's n r^2) then rests on one turn's q, and flagged 5 to 10 times its level on simulated
// sessions where the model holds (docs/gyroscope.md). So when the turns miss by far more than the
// noise model allows, the property the misses follow is named, not every property at once. One
// check per property; the family is flagged by Holm with the others.
std::vector<ResidualCheck> TurnShapeChecks(const GyroscopeMlResult& fit) {
  struct Property {
    const char* name;
    const char* what;
    const char* advice;
    double (*of)(const GyroscopeMlTurn&);
    ShapeClass shape_class;
  };
  static const Property kProperties[] = {
      {"turns_vs_abruptness", "how abruptly the rate changes between samples",
       "the samples do not resolve the turns' starts and stops: sample faster (or with the "
       "sensor's low-pass filter below half the rate), or start and stop each turn gently",
       [](const GyroscopeMlTurn& t) { return t.sampling_measure_rad; }, ShapeClass::kTurnMotion},
      {"turns_vs_peak_rate", "the turn's peak rate",
       "a gain that changes with the rate beyond the catalogue's terms, or an output near its "
       "range: turn more slowly, or calibrate at the rates of use",
       [](const GyroscopeMlTurn& t) { return t.peak_rate_rad_s; }, ShapeClass::kTurnMotion},
      {"turns_vs_angle", "the angle turned",
       "an error in proportion to the angle: a gain the model does not hold fixed (temperature, "
       "or a time base off)",
       [](const GyroscopeMlTurn& t) { return t.rotation_angle_rad; }, ShapeClass::kTurnMotion},
      {"turns_vs_duration", "the turn's duration",
       "an offset that moves during the turns (wander faster than the poses show, or a bias "
       "that depends on motion): shorter turns, or log temperature",
       [](const GyroscopeMlTurn& t) { return t.duration_s; }, ShapeClass::kTurnMotion},
      {"turns_vs_time", "the time in the session",
       "the gyroscope changes over the session (warm-up): let it warm up before the poses",
       [](const GyroscopeMlTurn& t) { return t.time_s; }, ShapeClass::kTime},
  };
  std::vector<ResidualCheck> checks;
  const size_t n = fit.turns.size();
  if (n < 4) return checks;
  for (const Property& property : kProperties) {
    std::vector<double> g(n), q(n);
    for (size_t t = 0; t < n; ++t) {
      const std::array<double, 2>& z = fit.turns[t].whitened;
      g[t] = property.of(fit.turns[t]);
      q[t] = 0.5 * (z[0] * z[0] + z[1] * z[1]);
    }
    g = Ranks(g);
    q = Ranks(q);
    const double g_mean = 0.5 * static_cast<double>(n + 1), q_mean = g_mean;
    double gg = 0.0, qq = 0.0, score = 0.0;
    for (size_t t = 0; t < n; ++t) {
      gg += (g[t] - g_mean) * (g[t] - g_mean);
      qq += (q[t] - q_mean) * (q[t] - q_mean);
      score += (g[t] - g_mean) * (q[t] - q_mean);
    }
    if (!(gg > 0.0) || !(qq > 0.0)) continue;
    ResidualCheck check;
    check.name = property.name;
    check.statistic = static_cast<double>(n - 1) * score * score / (gg * qq);
    check.dof = 1;
    check.p_value = ChiSquareSurvival(check.statistic, 1);
    check.shape_class = property.shape_class;
    check.description =
        StringPrintf("the turns' residuals %s with %s (rank correlation: chi2 %.1f on 1)",
                     score > 0.0 ? "grow" : "shrink", property.what, check.statistic);
    check.advice = property.advice;
    checks.push_back(check);
  }
  return checks;
}

}  // namespace

Status DiscoverGyroscope(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                         const TriadMlOptions& accelerometer_options,
                         const TriadMlResult& accelerometer,
                         const GyroscopeDiscoveryOptions& options,
                         GyroscopeDiscoveryResult* result) {
  *result = GyroscopeDiscoveryResult();
  if (!options.fit.effects.empty())
    return Status::Error("discovery starts from the gyroscope's 12 unknowns: no effects");
  // 1. Noise: the baseline, with a bias wander when the rest residuals reject white noise.
  GyroscopeMlOptions fit_options = options.fit;
  fit_options.bias_wander_fixed = false;
  fit_options.bias_wander_alpha = options.alpha / 4.0;
  fit_options.turn_sampling_fixed = false;
  fit_options.turn_sampling_alpha = options.turn_sampling ? options.alpha / 4.0 : 0.0;
  ACCELCAL_RETURN_IF_ERROR(CalibrateGyroscopeMl(log, intervals, accelerometer_options,
                                                accelerometer, fit_options, &result->baseline));
  const std::array<double, 3>& wander = result->baseline.bias_wander_variance;
  result->bias_wander = wander != std::array<double, 3>{};
  result->noise_note =
      result->bias_wander
          ? StringPrintf(
                "the poses' offsets scatter beyond their white noise (p = %.2g < alpha/4): a bias "
                "wander between poses of %.3g, %.3g, %.3g (sd, the output's unit) is the noise "
                "model",
                result->baseline.white_rest_p_value, std::sqrt(wander[0]), std::sqrt(wander[1]),
                std::sqrt(wander[2]))
          : StringPrintf("white noise (the poses' offsets scatter as it says, p = %.2g)",
                         result->baseline.white_rest_p_value);
  const double kappa2 = result->baseline.turn_sampling_variance;
  result->turn_sampling = kappa2 > 0.0;
  if (result->turn_sampling) {
    result->noise_note += StringPrintf(
        "; the turns miss by more than that allows (p = %.2g < alpha/4) as abruptly as their "
        "rates change between samples: the turns' sampling error, kappa = %.3g (the share of "
        "the rotation between two samples that the samples do not resolve), is the noise model",
        result->baseline.turns_without_sampling_p_value, std::sqrt(kappa2));
  }
  fit_options.bias_wander_fixed = true;
  fit_options.bias_wander_variance = wander;
  fit_options.turn_sampling_fixed = true;
  fit_options.turn_sampling_variance = kappa2;
  fit_options.earth_horizontal_fixed = true;
  fit_options.earth_horizontal_axis_variance = result->baseline.earth_horizontal_axis_variance;
  // Every later fit starts from the baseline's solution (the effects from 0).
  fit_options.initial = result->baseline.parameters;
  fit_options.offset_given = true;
  fit_options.initial_offset = result->baseline.offset;

  // 2. Effects: the one procedure.
  GyroscopeFitter fitter(log, intervals, accelerometer_options, accelerometer, fit_options);
  GyroscopeGeometry geometry(fitter, result->baseline, options.ambiguity_delta_chi2);
  SelectionOptions selection;
  selection.alpha = options.alpha / 2.0;
  selection.max_effects = options.max_effects;
  SelectionRecord record;
  std::vector<int> candidates;
  for (int e = 0; e < kGyroscopeEffectCount; ++e)
    if (GyroscopeEffectInfos()[e].not_a_candidate == nullptr) candidates.push_back(e);
  ACCELCAL_RETURN_IF_ERROR(SelectEffects(&geometry, candidates, selection, &record));
  const auto& infos = GyroscopeEffectInfos();
  for (const SelectionRecord::NotTested& entry : record.not_tested)
    result->not_tested.push_back(std::string(infos[entry.candidate].name) + ": " + entry.why);
  for (const SelectionRecord::Score& score : record.scores) {
    result->scores.push_back({score.step, infos[score.candidate].name, score.delta_chi2,
                              infos[score.candidate].coefficients, score.p_value,
                              score.significant});
  }
  std::vector<CandidateTest> necessity;
  ACCELCAL_RETURN_IF_ERROR(geometry.TestEffects(&necessity));
  // The final model with its own noise model: the wander the baseline needed may have been an
  // effect found (a g-sensitivity shifts each pose's offset), so it is estimated again.
  result->final_fit = geometry.current();
  if (!geometry.Effects().empty()) {
    GyroscopeMlOptions final_options = options.fit;
    final_options.solve.max_iterations =
        std::max(final_options.solve.max_iterations, kEffectFitIterations);
    final_options.bias_wander_alpha = options.alpha / 4.0;
    final_options.turn_sampling_alpha = options.turn_sampling ? options.alpha / 4.0 : 0.0;
    final_options.earth_horizontal_fixed = true;
    final_options.earth_horizontal_axis_variance = result->baseline.earth_horizontal_axis_variance;
    for (int group : geometry.Effects()) {
      const int first = GyroscopeEffectFirst(group);
      for (int c = first; c < first + GyroscopeEffectInfos()[group].coefficients; ++c)
        final_options.effects.push_back(c);
    }
    GyroscopeMlResult refit;
    if (CalibrateGyroscopeMl(log, intervals, accelerometer_options, accelerometer, final_options,
                             &refit)
            .ok()) {
      result->final_fit = refit;
    }
  }
  const GyroscopeMlResult& current = result->final_fit;
  result->final_bias_wander = current.bias_wander_variance != std::array<double, 3>{};
  result->final_turn_sampling = current.turn_sampling_variance > 0.0;
  std::vector<double> necessary;
  for (const CandidateTest& test : necessity) necessary.push_back(test.delta_chi2);
  const std::vector<int> model = geometry.Effects();
  for (size_t e = 0; e < model.size(); ++e) {
    const GyroscopeEffectInfo& info = infos[model[e]];
    GyroscopeFoundEffect found;
    found.effect = info.name;
    for (size_t i = kGyroscopeCalibrationCount; i < current.names.size(); ++i) {
      const int c = current.effects_estimated[i - kGyroscopeCalibrationCount];
      if (GyroscopeEffectOf(c) != model[e]) continue;
      found.names.push_back(current.names[i]);
      found.estimates.push_back(current.effects[c]);
      found.stddevs.push_back(current.stddev[i]);
    }
    if (necessity[e].delta_chi2 != HUGE_VAL) {
      found.delta_chi2 = necessity[e].delta_chi2;
      found.p_value = necessity[e].p_value;
    }
    result->effects.push_back(found);
  }
  for (const LookAlike& look_alike :
       FindLookAlikes(geometry, candidates, FitSwaps(&geometry, candidates), necessary)) {
    result->look_alikes.push_back({infos[model[look_alike.effect]].name,
                                   infos[look_alike.alternative].name, look_alike.fit.worse});
  }

  // 3. What remains: the turns' chi-square (not when the turns' sampling error was estimated
  // from it: it then fits by construction) and their shapes.
  for (const ResidualCheck& check : TurnShapeChecks(current)) result->checks.push_back(check);
  if (!result->final_turn_sampling) {
    const int turn_components = 2 * static_cast<int>(current.turns.size());
    ResidualCheck turns =
        ChiSquareCheck("turns_chi2", current.chi2_turns, turn_components, "the turns' residuals");
    turns.advice =
        "the calibrated rates miss the turns by more than the noise allows (a time offset "
        "between the sensors, dropped samples, or an effect the model does not know)";
    result->checks.push_back(turns);
  }
  if (!result->final_bias_wander) {
    ResidualCheck rest = ChiSquareCheck(
        "rest_chi2", current.chi2_rest,
        std::max(1, 3 * static_cast<int>(current.rest_means.size()) - 3), "the poses' offsets");
    rest.shape_class = ShapeClass::kPoseOrder;
    rest.advice = "the poses' offsets scatter beyond the noise model";
    result->checks.push_back(rest);
  }
  FlagByHolm(options.alpha / 4.0, &result->checks);
  // The verdict names a shape before the scatter, the strongest shape first.
  std::vector<const ResidualCheck*> flagged;
  for (const ResidualCheck& check : result->checks)
    if (check.flagged) flagged.push_back(&check);
  std::stable_sort(flagged.begin(), flagged.end(),
                   [](const ResidualCheck* a, const ResidualCheck* b) {
                     const bool a_shape = a->dof == 1, b_shape = b->dof == 1;
                     if (a_shape != b_shape) return a_shape;
                     return a_shape && a->statistic > b->statistic;
                   });
  for (const ResidualCheck* check : flagged) result->remaining.push_back(WhatRemains(*check));

  // The verdict.
  std::string found;
  for (const GyroscopeFoundEffect& effect : result->effects) {
    found += (found.empty() ? "" : ", ") + effect.effect +
             StringPrintf(" (chi2 %.1f on %zu, p = %.2g)", effect.delta_chi2, effect.names.size(),
                          effect.p_value);
  }
  if (result->final_turn_sampling) {
    found = StringPrintf("the turns' sampling error (kappa = %.3g)",
                         std::sqrt(current.turn_sampling_variance)) +
            (found.empty() ? "" : "; " + found);
  }
  if (result->final_bias_wander)
    found = "a bias wander between poses" + (found.empty() ? "" : "; " + found);
  else if (result->bias_wander && !result->effects.empty())
    result->noise_note += "; with the effects found, the final model's poses need no wander";
  result->verdict_code =
      DecideVerdict(!result->remaining.empty(), !result->look_alikes.empty(), !found.empty());
  switch (result->verdict_code) {
    case Verdict::kUnexplained:
      result->verdict = "unexplained structure remains: " + result->remaining.front() +
                        (found.empty() ? "" : " (found: " + found + ")");
      break;
    case Verdict::kCannotTellApart:
      result->verdict =
          "cannot tell apart: " + result->look_alikes.front().effect + " and " +
          result->look_alikes.front().alternative +
          StringPrintf(" fit within %.1f of each other", result->look_alikes.front().worse);
      break;
    case Verdict::kMissing:
      result->verdict = "missing from the 12-unknown model, found: " + found +
                        "; the extended model explains the turns";
      break;
    case Verdict::kExplained:
      result->verdict = StringPrintf(
          "the 12-unknown model explains the gyroscope: no effect is significant at "
          "alpha = %g, and nothing remains that the checks see",
          options.alpha);
      break;
  }
  // Of the model settled on, the calibration written (issue 44, item 7): its final fit when it
  // found effects.
  result->poorly_determined = PoorlyDeterminedGyroscopeParameters(
      result->effects.empty() ? result->baseline : result->final_fit,
      GyroscopeOutputUnitName(options.fit.unit), options.determination);
  result->verdict += PoorlyDeterminedClause(result->poorly_determined);
  return Status::Ok();
}

}  // namespace accelcal
