#include "reporting/discovery_report.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "common/format.h"
#include "estimation/tilt_table/parameter_estimate.h"
#include "reporting/estimate_json.h"

namespace accelcal {
namespace {

const char* const kAxisName[2] = {"x", "y"};

// `value` printed with `format`, or "n/a" when it is not finite (an undefined figure).
std::string Figure(const char* format, double value) {
  return std::isfinite(value) ? StringPrintf(format, value) : std::string("n/a");
}

// `value`, or null when it is not finite (JSON has no NaN, and the writer refuses one).
nlohmann::json Finite(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

// The first `shown` of `samples`, comma-separated.
std::string SampleList(const std::vector<int>& samples, size_t shown = 10) {
  std::string text;
  for (size_t i = 0; i < samples.size() && i < shown; ++i)
    text += (i ? ", " : "") + std::to_string(samples[i]);
  if (samples.size() > shown) text += ", ...";
  return text;
}

const char* EventName(SelectionEvent::Kind kind) {
  return kind == SelectionEvent::Kind::kAdded ? "added" : "dropped";
}

// Why an effect left the model, or null for an addition.
nlohmann::json EventReason(SelectionEvent::Kind kind) {
  switch (kind) {
    case SelectionEvent::Kind::kAdded:
      return nullptr;
    case SelectionEvent::Kind::kDropped:
      return "not_needed";
    case SelectionEvent::Kind::kDroppedForShape:
      return "remaining_structure";
  }
  return nullptr;
}

// The cross-validation's extended figure against what it would be for a right model.
std::string CrossValidationComment(const CrossValidation& cv) {
  if (!(cv.null_stddev > 0.0) || !std::isfinite(cv.z)) return "";
  if (cv.z > 3.0) return "above its null spread: the model misses something";
  if (cv.z < -3.0) return "below its null spread: the noise is smaller than its model says";
  return "within its null spread";
}

// The checks, most significant first.
std::vector<const ResidualCheck*> StrongestChecks(const std::vector<ResidualCheck>& checks) {
  std::vector<const ResidualCheck*> sorted;
  for (const ResidualCheck& check : checks) sorted.push_back(&check);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const ResidualCheck* a, const ResidualCheck* b) {
                     if (a->flagged != b->flagged) return a->flagged;
                     return a->p_value < b->p_value;
                   });
  return sorted;
}

const LandmarkScore* Tied(const LandmarkDecision& decision, const std::string& name) {
  for (const LandmarkScore& score : decision.scores) {
    if (score.landmark.name == name) return &score;
  }
  return nullptr;
}

// Per axis: what the noise analysis of the baseline's residuals found, the noise model the
// final fit used, and what was named.
std::string NoiseBlock(const DiscoveryResult& result) {
  if (result.noise_analysis[0].samples == 0 && result.noise_analysis[1].samples == 0) return "";
  // clang-format off
  std::string text =
      "\n  noise (the baseline's residuals, read from local differences; p two-sided, kurtosis one-sided)\n"
      "  axis  level ratio             p   lag-1 correlation        p   outliers (largest, p)       excess kurtosis (p)\n";
  // clang-format on
  for (int k = 0; k < 2; ++k) {
    const NoiseAnalysis& a = result.noise_analysis[k];
    const std::string level =
        Figure("%.4f", a.variance_ratio) + " +- " + Figure("%.4f", a.variance_ratio_stddev);
    const std::string correlation =
        Figure("%+.4f", a.correlation) + " +- " + Figure("%.4f", a.correlation_stddev);
    const std::string outliers =
        StringPrintf("%zu (%s sigma, p %s)", a.outlier_candidates.size(),
                     Figure("%.1f", a.largest_score).c_str(), Figure("%.2g", a.outlier_p).c_str());
    text += StringPrintf("  %-4s  %-17s %7s   %-18s %7s   %-27s %s (p %s)%s\n", kAxisName[k],
                         level.c_str(), Figure("%.2g", a.level_p).c_str(), correlation.c_str(),
                         Figure("%.2g", a.correlation_p).c_str(), outliers.c_str(),
                         Figure("%+.3g", a.excess_kurtosis).c_str(),
                         Figure("%.2g", a.kurtosis_p).c_str(),
                         a.moments_from_sample ? "  (sds from the sample's moments)" : "");
  }
  for (int k = 0; k < 2; ++k) {
    const NoiseAnalysis& a = result.noise_analysis[k];
    if (a.outlier_candidates.empty()) continue;
    text += StringPrintf(
        "  %s: %zu outlier candidates, %s: samples %s\n", kAxisName[k], a.outlier_candidates.size(),
        result.noise_model[k].outliers.empty() ? "kept in the fit" : "set aside in the fit",
        SampleList(a.outlier_candidates).c_str());
  }
  text += "  noise model of the final fit:";
  for (int k = 0; k < 2; ++k) {
    const AxisNoise& noise = result.noise_model[k];
    text += StringPrintf("%s %s variance %s (m/s^2)^2, correlation %s, %zu samples set aside",
                         k == 0 ? "" : ";", kAxisName[k], Figure("%.4g", noise.variance).c_str(),
                         Figure("%.3g", noise.correlation).c_str(), noise.outliers.size());
  }
  text += result.robust_fit ? "; estimates by Huber's loss (sandwich covariance)\n" : "\n";
  std::string named;
  for (int k = 0; k < 2; ++k) {
    if (!result.axes[k].noise_flagged) continue;
    named += StringPrintf("    %-20s %s: level ratio %s +- %s of the stated (p = %s)\n",
                          k == 0 ? "noise_variance_x" : "noise_variance_y", kAxisName[k],
                          Figure("%.4g", result.noise_analysis[k].variance_ratio).c_str(),
                          Figure("%.2g", result.noise_analysis[k].variance_ratio_stddev).c_str(),
                          Figure("%.2g", result.noise_analysis[k].level_p).c_str());
  }
  for (const NoiseFinding& finding : result.noise_findings) {
    named +=
        StringPrintf("    %-20s %s\n", NoiseFindingName(finding.kind), finding.description.c_str());
  }
  text +=
      named.empty() ? "  named: nothing (white noise at the stated level)\n" : "  named:\n" + named;
  return text;
}

// What the final model leaves: the flagged checks' sentences, then the strongest checks.
std::string RemainsBlock(const DiscoveryResult& result) {
  if (result.checks.empty() && result.remaining.empty()) return "";
  // clang-format off
  std::string text =
      "\n  what remains (checks of the final model's residuals, Holm within their share of alpha)\n";
  // clang-format on
  if (result.remaining.empty()) {
    text += "  nothing the checks can see\n";
  } else {
    // Each line with the class of its shape: what it is a function of.
    for (size_t i = 0; i < result.remaining.size(); ++i) {
      const std::string shape_class =
          i < result.remaining_checks.size()
              ? StringPrintf("[%s] ",
                             ShapeClassName(result.checks[result.remaining_checks[i]].shape_class))
              : "";
      text += "  - " + shape_class + result.remaining[i] + "\n";
    }
  }
  const std::vector<const ResidualCheck*> sorted = StrongestChecks(result.checks);
  size_t shown = 0;
  for (const ResidualCheck* check : sorted) shown += check->flagged;
  shown = std::min(sorted.size(), std::max<size_t>(shown, 5));
  if (shown > 0) {
    text += StringPrintf(
        "  strongest of %zu checks     class              statistic     dof      p-value  "
        "flagged\n",
        sorted.size());
    for (size_t i = 0; i < shown; ++i) {
      const ResidualCheck& check = *sorted[i];
      text +=
          StringPrintf("  %-24s %-15s %12s %7s %12s  %s\n", check.name.c_str(),
                       ShapeClassName(check.shape_class), Figure("%.2f", check.statistic).c_str(),
                       Figure("%.0f", check.dof).c_str(), Figure("%.3g", check.p_value).c_str(),
                       check.flagged ? "yes" : "");
    }
  }
  return text;
}

// Effects of the final model another candidate would replace at about the same fit.
std::string AmbiguityBlock(const DiscoveryResult& result) {
  if (result.ambiguities.empty()) return "";
  std::string text =
      "\n  cannot tell apart (effects another candidate replaces at about the same fit, or one "
      "beside "
      "them moves)\n";
  for (const Ambiguity& ambiguity : result.ambiguities) {
    const ParameterInfo& info = Info(ambiguity.effect);
    text += StringPrintf("  %-24s = %s +- %s %s  (in the final model)\n", info.name,
                         Figure("%+.4e", ambiguity.effect_estimate).c_str(),
                         Figure("%.3e", ambiguity.effect_stddev).c_str(), info.unit);
    for (const Ambiguity::Alternative& alternative : ambiguity.alternatives) {
      const std::string other_name = alternative.Name();
      const std::string other_unit = alternative.Unit();
      if (alternative.Partner()) {
        const std::string where =
            alternative.beside ? std::string("beside it") +
                                     (alternative.note.empty() ? "" : ", " + alternative.note)
                               : std::string("in ") + Info(*alternative.replaces).name + "'s place";
        text += StringPrintf(
            "    or with %-16s = %s +- %s %s %s, %s = %s +- %s %s  (delta chi2 %s)\n",
            other_name.c_str(), Figure("%+.4e", alternative.estimate).c_str(),
            Figure("%.3e", alternative.stddev).c_str(), other_unit.c_str(), where.c_str(),
            info.name, Figure("%+.4e", alternative.effect_estimate_with).c_str(),
            Figure("%.3e", alternative.effect_stddev_with).c_str(), info.unit,
            Figure("%+.2f", alternative.delta_chi2).c_str());
        continue;
      }
      text += StringPrintf("    or %-21s = %s +- %s %s  (delta chi2 %s)\n", other_name.c_str(),
                           Figure("%+.4e", alternative.estimate).c_str(),
                           Figure("%.3e", alternative.stddev).c_str(), other_unit.c_str(),
                           Figure("%+.2f", alternative.delta_chi2).c_str());
    }
    if (!ambiguity.separation.empty())
      text += "    what would tell them apart: " + ambiguity.separation + "\n";
  }
  return text;
}

// The effects under every plausible landmark tie (TieDependence, discovery.h); null when
// nothing depends on the tie or only one tie is plausible.
nlohmann::json TieDependenceJson(const TieDependence& dependence) {
  if (!dependence.Depends()) return nullptr;
  nlohmann::json names = nlohmann::json::array(), run_names = nlohmann::json::array();
  for (const Parameter effect : dependence.effects) {
    names.push_back(Info(effect).name);
    if (ActsOnlyInRun(effect)) run_names.push_back(Info(effect).name);
  }
  nlohmann::json ties = nlohmann::json::array();
  for (const TieAlternative& tie : dependence.ties) {
    nlohmann::json estimates = nlohmann::json::object(), stddev = nlohmann::json::object();
    for (size_t e = 0; e < dependence.effects.size(); ++e) {
      estimates[Info(dependence.effects[e]).name] = Finite(tie.estimates[e]);
      stddev[Info(dependence.effects[e]).name] = Finite(tie.stddevs[e]);
    }
    ties.push_back({{"landmark", tie.landmark},
                    {"posterior", Finite(tie.posterior)},
                    {"tied", tie.tied},
                    {"estimates", estimates},
                    {"stddev", stddev},
                    {"delta_chi2", Finite(tie.delta_chi2)},
                    {"p_value", Finite(tie.p_value)},
                    {"needed", tie.needed}});
  }
  return {{"effects", names},
          {"run_effects", run_names},
          {"undecided", dependence.Undecided()},
          {"posterior_reported", kTiePosteriorReported},
          {"shift_sigma", kTieShiftSigma},
          {"ties", ties}};
}

std::string CrossValidationLine(const CrossValidation& cv) {
  if (cv.folds <= 0) return "";
  // clang-format off
  std::string text = StringPrintf(
      "  cross-validation (%d contiguous theta blocks): held-out mean squared whitened error %s baseline, %s extended\n",
      // clang-format on
      cv.folds, Figure("%.4f", cv.baseline).c_str(), Figure("%.4f", cv.extended).c_str());
  const std::string comment = CrossValidationComment(cv);
  if (!comment.empty()) {
    text += StringPrintf(
        "    a right model would give %s +- %s; z = %s: %s\n", Figure("%.4f", cv.null_mean).c_str(),
        Figure("%.4f", cv.null_stddev).c_str(), Figure("%+.2f", cv.z).c_str(), comment.c_str());
  }
  return text;
}

}  // namespace

std::string DiscoveryText(const DiscoveryResult& result, double alpha) {
  std::string text =
      "accelcal discover: does the baseline explain the data?\n\n  verdict: " + result.verdict +
      "\n";
  text += StringPrintf("  in short: %s (of explained, missing, unexplained, cannot_tell_apart)\n",
                       VerdictCode(result.verdict_code));
  text += NoiseBlock(result);
  text += RemainsBlock(result);
  text += AmbiguityBlock(result);

  text += "\n  what the baseline leaves (residuals against the stated noise)\n";
  text +=
      "  axis  noise ratio (von Neumann)      p   chi2/dof  Ljung-Box Q(p)       Jarque-Bera (p)\n";
  for (int k = 0; k < 2; ++k) {
    const AxisDiagnostics& a = result.axes[k];
    text += StringPrintf(
        "  %-4s  %6s +- %s %s  %9s  %8s  %8s (%7s)  %8s (%s)\n", kAxisName[k],
        Figure("%6.4f", a.noise.ratio).c_str(), Figure("%.4f", a.noise.ratio_stddev).c_str(),
        a.noise_flagged ? "(off)" : "     ", Figure("%9.2g", a.noise.p_value).c_str(),
        Figure("%8.4f", a.dof > 0 ? a.chi2 / a.dof : NAN).c_str(),
        Figure("%8.1f", a.whiteness.q).c_str(), Figure("%7.2g", a.whiteness.p_value).c_str(),
        Figure("%8.2f", a.normality.jarque_bera).c_str(),
        Figure("%.2g", a.normality.p_value).c_str());
  }
  // The largest binned residual, in its standard error: where a model term is missing.
  for (int k = 0; k < 2; ++k) {
    double worst = 0.0;
    double at = 0.0;
    for (const ResidualBin& bin : result.axes[k].bins) {
      const double z = bin.mean / bin.standard_error;
      if (bin.count > 0 && std::isfinite(z) && std::abs(z) > std::abs(worst)) {
        worst = z;
        at = bin.theta_center_rad;
      }
    }
    text += StringPrintf(
        "  axis %s: largest binned residual %+.1f standard errors at theta = %.2f rad (%zu bins)\n",
        kAxisName[k], worst, at, result.axes[k].bins.size());
  }
  text += "  endpoint: " +
          (result.landmark_note.empty() ? std::string("no landmarks") : result.landmark_note) +
          "\n";

  // clang-format off
  text += StringPrintf(
      "\n  candidates (score test, 1 dof each; Holm at alpha/2 = %g among those left at each step, the other\n"
      // clang-format on
      "  alpha/2 going to the noise tests and the checks of what remains)\n",
      alpha / 2);
  text += "  step  effect                  delta chi2        p-value  significant\n";
  for (const CandidateScore& c : result.candidates) {
    text += StringPrintf("  %4d  %-22s %11s %14s  %s\n", c.step, Info(c.effect).name,
                         Figure("%.2f", c.delta_chi2).c_str(), Figure("%.3g", c.p_value).c_str(),
                         c.significant ? "yes" : "");
  }
  bool dropped = false;
  for (const SelectionEvent& event : result.history)
    dropped |= event.kind != SelectionEvent::Kind::kAdded;
  if (dropped) {
    // clang-format off
    text +=
        "\n  how the model grew (backward elimination drops what a later effect explains, or what the\n  remaining structure explains)\n";
    // clang-format on
    for (const SelectionEvent& event : result.history) {
      text += StringPrintf("  %-8s %-22s delta chi2 %8s  p %9s  (run tied to %s)%s\n",
                           EventName(event.kind), Info(event.effect).name,
                           Figure("%.2f", event.delta_chi2).c_str(),
                           Figure("%.3g", event.p_value).c_str(),
                           event.landmark.empty() ? "none" : event.landmark.c_str(),
                           event.kind == SelectionEvent::Kind::kDroppedForShape
                               ? "; dropped: explained by the remaining structure"
                               : "");
    }
  }
  if (!result.effects.empty()) {
    // clang-format off
    text +=
        "\n  effects (final model; delta chi2, p and BIC against the final model without the effect)\n"
        "                                  estimate       1 sigma  unit        delta chi2   p-value   delta BIC\n";
    // clang-format on
    for (const DiscoveredEffect& e : result.effects) {
      text += StringPrintf("  %-28s %12s  %12s  %-10s %10s %9s  %10s\n", Info(e.effect).name,
                           Figure("%+.4e", e.estimate).c_str(), Figure("%.3e", e.stddev).c_str(),
                           Info(e.effect).unit, Figure("%.1f", e.delta_chi2).c_str(),
                           Figure("%.2g", e.p_value).c_str(), Figure("%.1f", e.bic_change).c_str());
    }
    // clang-format off
    text +=
        "\n  gain: the baseline parameters in the extended model, shifted by (in the baseline's sigma)\n  ";
    // clang-format on
    const ParameterEstimate baseline = FromBaselineFit(result.baseline);
    for (const Parameter parameter : baseline.free) {
      text += StringPrintf(
          " %s %s", Info(parameter).name,
          Figure("%+.2f", (result.extended.estimate.Value(parameter) - baseline.Value(parameter)) /
                              baseline.StandardDeviation(parameter))
              .c_str());
    }
    text += "\n";
  } else {
    text += "\n";
  }
  text += CrossValidationLine(result.cross_validation);
  text += "\n  endpoint (m)            x          y     1 sigma x, y    reached";
  if (!result.tied_landmark.empty())
    text += StringPrintf("    posterior of %s", result.tied_landmark.c_str());
  text += "\n";
  for (const auto& [name, trajectory, decision] :
       {std::make_tuple("baseline", &result.baseline_trajectory, &result.baseline_decision),
        std::make_tuple("extended", &result.extended_trajectory, &result.extended_decision)}) {
    text += StringPrintf("  %-10s     %10s %10s   %6s, %6s   %-16s", name,
                         Figure("%10.3f", trajectory->endpoint.x()).c_str(),
                         Figure("%10.3f", trajectory->endpoint.y()).c_str(),
                         Figure("%6.2f", std::sqrt(trajectory->covariance(0, 0))).c_str(),
                         Figure("%6.2f", std::sqrt(trajectory->covariance(1, 1))).c_str(),
                         decision->reached.empty() ? "none consistent" : decision->reached.c_str());
    if (const LandmarkScore* score = Tied(*decision, result.tied_landmark))
      text += " " + Figure("%.3g", score->posterior);
    text += "\n";
  }
  return text;
}

nlohmann::json DiscoveryJson(const DiscoveryResult& result, double alpha) {
  nlohmann::json effects = nlohmann::json::array();
  for (const DiscoveredEffect& e : result.effects) {
    effects.push_back({{"name", Info(e.effect).name},
                       {"estimate", e.estimate},
                       {"stddev", e.stddev},
                       {"p_value", e.p_value},
                       {"delta_chi2", e.delta_chi2},
                       {"delta_bic", e.bic_change},
                       {"selected_at_step", e.selection_step},
                       {"delta_chi2_at_selection", e.selection_delta_chi2},
                       {"p_value_at_selection", e.selection_p_value}});
  }
  nlohmann::json history = nlohmann::json::array();
  for (const SelectionEvent& event : result.history) {
    history.push_back({{"change", EventName(event.kind)},
                       {"reason", EventReason(event.kind)},
                       {"name", Info(event.effect).name},
                       {"delta_chi2", event.delta_chi2},
                       {"p_value", event.p_value},
                       {"tied_landmark", event.landmark.empty() ? nlohmann::json(nullptr)
                                                                : nlohmann::json(event.landmark)}});
  }
  nlohmann::json candidates = nlohmann::json::array();
  for (const CandidateScore& c : result.candidates) {
    candidates.push_back({{"step", c.step},
                          {"name", Info(c.effect).name},
                          {"delta_chi2", c.delta_chi2},
                          {"p_value", c.p_value},
                          {"significant", c.significant}});
  }
  nlohmann::json noise = nlohmann::json::object();
  for (int k = 0; k < 2; ++k) {
    const AxisDiagnostics& a = result.axes[k];
    noise[k == 0 ? "x" : "y"] = {{"ratio", a.noise.ratio},
                                 {"ratio_stddev", a.noise.ratio_stddev},
                                 {"p_value", a.noise.p_value},
                                 {"flagged", a.noise_flagged},
                                 {"chi2", a.chi2},
                                 {"dof", a.dof},
                                 {"ljung_box_q", a.whiteness.q},
                                 {"ljung_box_p", a.whiteness.p_value},
                                 {"jarque_bera", a.normality.jarque_bera},
                                 {"jarque_bera_p", a.normality.p_value}};
    const NoiseAnalysis& n = result.noise_analysis[k];
    nlohmann::json& axis = noise[kAxisName[k]];
    axis["analysis"] = {{"samples", n.samples},
                        {"variance_ratio", Finite(n.variance_ratio)},
                        {"variance_ratio_stddev", Finite(n.variance_ratio_stddev)},
                        {"level_z", Finite(n.level_z)},
                        {"level_p", Finite(n.level_p)},
                        {"correlation", Finite(n.correlation)},
                        {"correlation_stddev", Finite(n.correlation_stddev)},
                        {"correlation_z", Finite(n.correlation_z)},
                        {"correlation_p", Finite(n.correlation_p)},
                        {"largest_outlier_score", Finite(n.largest_score)},
                        {"outlier_p", Finite(n.outlier_p)},
                        {"outlier_candidates", n.outlier_candidates},
                        {"excess_kurtosis", Finite(n.excess_kurtosis)},
                        {"kurtosis_z", Finite(n.kurtosis_z)},
                        {"kurtosis_p", Finite(n.kurtosis_p)},
                        {"moments_from_sample", n.moments_from_sample}};
    const AxisNoise& model = result.noise_model[k];
    axis["model"] = {{"variance", Finite(model.variance)},
                     {"correlation", Finite(model.correlation)},
                     {"outliers", model.outliers}};
    axis["variance_used"] = Finite(result.noise_variance_used[k]);
    nlohmann::json findings = nlohmann::json::array();
    for (const NoiseFinding& finding : result.noise_findings) {
      if (finding.axis != k) continue;
      findings.push_back({{"name", NoiseFindingName(finding.kind)},
                          {"estimate", Finite(finding.estimate)},
                          {"stddev", Finite(finding.stddev)},
                          {"p_value", Finite(finding.p_value)},
                          {"samples", finding.samples},
                          {"description", finding.description}});
    }
    axis["findings"] = findings;
  }
  nlohmann::json checks = nlohmann::json::array();
  for (const ResidualCheck& check : result.checks) {
    checks.push_back(
        {{"name", check.name},
         {"axis", check.axis >= 0 && check.axis < 2 ? nlohmann::json(kAxisName[check.axis])
                                                    : nlohmann::json(nullptr)},
         {"statistic", Finite(check.statistic)},
         {"dof", Finite(check.dof)},
         {"p_value", Finite(check.p_value)},
         {"flagged", check.flagged},
         {"description", check.description},
         {"shape_class", ShapeClassName(check.shape_class)},
         {"advice", check.advice}});
  }
  // The verdict's shapes, strongest first.
  nlohmann::json remaining_shapes = nlohmann::json::array();
  for (const int index : result.remaining_checks) {
    const ResidualCheck& check = result.checks[index];
    remaining_shapes.push_back({{"check", check.name},
                                {"shape_class", ShapeClassName(check.shape_class)},
                                {"description", check.description},
                                {"advice", check.advice}});
  }
  nlohmann::json ambiguities = nlohmann::json::array();
  for (const Ambiguity& ambiguity : result.ambiguities) {
    nlohmann::json alternatives = nlohmann::json::array();
    for (const Ambiguity::Alternative& alternative : ambiguity.alternatives) {
      alternatives.push_back(
          {{"name", alternative.Name()},
           {"outside_catalogue", !alternative.shape.empty()},
           {"unit", alternative.Unit()},
           {"estimate", Finite(alternative.estimate)},
           {"stddev", Finite(alternative.stddev)},
           {"delta_chi2", Finite(alternative.delta_chi2)},
           {"beside", alternative.beside},
           {"replaces", alternative.replaces ? nlohmann::json(Info(*alternative.replaces).name)
                                             : nlohmann::json(nullptr)},
           {"effect_estimate_with",
            alternative.Partner() ? Finite(alternative.effect_estimate_with) : nullptr},
           {"effect_stddev_with",
            alternative.Partner() ? Finite(alternative.effect_stddev_with) : nullptr},
           {"p_value", alternative.Partner() ? Finite(alternative.p_value) : nullptr},
           {"note", alternative.note.empty() ? nlohmann::json(nullptr)
                                             : nlohmann::json(alternative.note)}});
    }
    ambiguities.push_back({{"name", Info(ambiguity.effect).name},
                           {"unit", Info(ambiguity.effect).unit},
                           {"estimate", Finite(ambiguity.effect_estimate)},
                           {"stddev", Finite(ambiguity.effect_stddev)},
                           {"alternatives", alternatives},
                           {"separation", ambiguity.separation}});
  }
  const CrossValidation& cv = result.cross_validation;
  const bool has_null = cv.folds > 0 && cv.null_stddev > 0.0;
  const auto if_folds = [&](double value) {
    return cv.folds > 0 ? nlohmann::json(value) : nlohmann::json(nullptr);
  };
  nlohmann::json cross_validation = {{"folds", cv.folds},
                                     {"baseline", if_folds(cv.baseline)},
                                     {"extended", if_folds(cv.extended)},
                                     {"null_mean", has_null ? Finite(cv.null_mean) : nullptr},
                                     {"null_stddev", has_null ? Finite(cv.null_stddev) : nullptr},
                                     {"z", has_null ? Finite(cv.z) : nullptr}};
  const std::string comment = CrossValidationComment(cv);
  cross_validation["comment"] = comment.empty() ? nlohmann::json(nullptr) : nlohmann::json(comment);
  nlohmann::json shifts = nlohmann::json::object();
  const ParameterEstimate baseline = FromBaselineFit(result.baseline);
  for (const Parameter parameter : baseline.free) {
    shifts[Info(parameter).name] =
        (result.extended.estimate.Value(parameter) - baseline.Value(parameter)) /
        baseline.StandardDeviation(parameter);
  }
  const LandmarkScore* before = Tied(result.baseline_decision, result.tied_landmark);
  const LandmarkScore* after = Tied(result.extended_decision, result.tied_landmark);
  return {// clang-format off
      {"problem", "discover"},
      {"alpha", alpha},
      {"verdict", result.verdict},
      {"verdict_code", VerdictCode(result.verdict_code)},
      {"effects", effects},
      {"effects_figures",
       "delta_chi2, p_value and delta_bic of each effect are against the final model: the chi-square the final model gains over itself without that effect, with the same landmark tie; the *_at_selection figures are those of the step that added it"},
          // clang-format on
          {"history", history},
          {"candidates", candidates},
          {"noise", noise},
          {"robust_fit", result.robust_fit},
          {"checks", checks},
          {"remaining", result.remaining},
          {"remaining_shapes", remaining_shapes},
          {"ambiguities", ambiguities},
          {"tie_dependence", TieDependenceJson(result.tie_dependence)},
          {"reached", ReachedJson(result.extended_decision)},
          {"tied_landmark", result.tied_landmark.empty() ? nlohmann::json(nullptr)
                                                         : nlohmann::json(result.tied_landmark)},
          {"landmark_note", result.landmark_note.empty() ? nlohmann::json(nullptr)
                                                         : nlohmann::json(result.landmark_note)},
          {"baseline",
           SolutionJson(baseline, result.baseline.chi2_x.chi2, result.baseline.chi2_y.chi2,
                        std::nullopt, result.baseline_trajectory, result.baseline_decision)},
          {"extended",
           SolutionJson(result.extended.estimate, result.extended.chi2_x, result.extended.chi2_y,
                        result.tied_landmark.empty()
                            ? std::nullopt
                            : std::optional<double>(result.extended.chi2_endpoint),
                        result.extended_trajectory, result.extended_decision)},
          {"gain",
           {{"baseline_shift_sigma", shifts},
            {"cross_validation", cross_validation},
            {"posterior_before", before != nullptr ? nlohmann::json(before->posterior) : nullptr},
            {"posterior_after", after != nullptr ? nlohmann::json(after->posterior) : nullptr}}}};
}

std::string DiscoveryBinsCsv(const DiscoveryResult& result) {
  std::string text = "theta_rad,count,mean_x,se_x,signature_x,mean_y,se_y,signature_y\n";
  const auto& x = result.axes[0];
  const auto& y = result.axes[1];
  for (size_t b = 0; b < x.bins.size(); ++b) {
    text += StringPrintf("%.6f,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", x.bins[b].theta_center_rad,
                         x.bins[b].count, x.bins[b].mean, x.bins[b].standard_error,
                         b < x.bin_signature.size() ? x.bin_signature[b] : 0.0, y.bins[b].mean,
                         y.bins[b].standard_error,
                         b < y.bin_signature.size() ? y.bin_signature[b] : 0.0);
  }
  return text;
}

std::string DiscoveryResidualsCsv(const DiscoveryResult& result, const CalibrationTest& test,
                                  int max_rows) {
  std::string text = "sample,theta_rad,residual_x,residual_y,outlier_x,outlier_y\n";
  const int samples = std::min({test.size(), static_cast<int>(result.final_residuals[0].size()),
                                static_cast<int>(result.final_residuals[1].size())});
  if (samples == 0) return text;
  const int rows = std::min(samples, std::max(2, max_rows));
  std::vector<int> chosen;
  chosen.reserve(rows);
  for (int row = 0; row < rows; ++row) {
    // Evenly spread, the first and the last sample included.
    chosen.push_back(
        rows == 1 ? 0
                  : static_cast<int>((static_cast<long long>(row) * (samples - 1)) / (rows - 1)));
  }
  if (rows < samples) {
    // The samples set aside as outliers too (a fifth of max_rows at most), so the plot shows
    // where they are.
    std::vector<int> outliers;
    std::set_union(result.noise_model[0].outliers.begin(), result.noise_model[0].outliers.end(),
                   result.noise_model[1].outliers.begin(), result.noise_model[1].outliers.end(),
                   std::back_inserter(outliers));
    outliers.erase(std::remove_if(outliers.begin(), outliers.end(),
                                  [&](int i) { return i < 0 || i >= samples; }),
                   outliers.end());
    if (static_cast<int>(outliers.size()) > max_rows / 5) outliers.resize(max_rows / 5);
    std::vector<int> merged;
    std::set_union(chosen.begin(), chosen.end(), outliers.begin(), outliers.end(),
                   std::back_inserter(merged));
    chosen.swap(merged);
  }
  for (const int i : chosen) {
    const double x = result.final_residuals[0][i];
    const double y = result.final_residuals[1][i];
    text += StringPrintf("%d,%.9g,%s,%s,%d,%d\n", i, test.theta_rad[i],
                         std::isfinite(x) ? StringPrintf("%.9g", x).c_str() : "",
                         std::isfinite(y) ? StringPrintf("%.9g", y).c_str() : "",
                         result.noise_model[0].IsOutlier(i) ? 1 : 0,
                         result.noise_model[1].IsOutlier(i) ? 1 : 0);
  }
  return text;
}

}  // namespace accelcal
