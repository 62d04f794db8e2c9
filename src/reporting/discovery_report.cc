#include "reporting/discovery_report.h"

#include <cmath>

#include "common/format.h"
#include "estimation/parameter_estimate.h"

namespace accelcal {
namespace {

const LandmarkScore* Tied(const LandmarkDecision& decision, const std::string& name) {
  for (const LandmarkScore& score : decision.scores) {
    if (score.landmark.name == name) return &score;
  }
  return nullptr;
}

nlohmann::json Side(const ParameterEstimate& estimate, double chi2_x, double chi2_y,
                    double chi2_endpoint, const DeadReckoningResult& trajectory,
                    const LandmarkDecision& decision) {
  nlohmann::json parameters = nlohmann::json::object();
  nlohmann::json stddev = nlohmann::json::object();
  for (const Parameter parameter : estimate.free) {
    parameters[Info(parameter).name] = estimate.Value(parameter);
    stddev[Info(parameter).name] = estimate.StandardDeviation(parameter);
  }
  nlohmann::json landmarks = nlohmann::json::array();
  for (const LandmarkScore& score : decision.scores) {
    landmarks.push_back({{"name", score.landmark.name},
                         {"x", score.landmark.x_m},
                         {"y", score.landmark.y_m},
                         {"mahalanobis2", score.mahalanobis2},
                         {"posterior", score.posterior},
                         {"p_value", score.p_value}});
  }
  return {{"parameters", parameters},
          {"stddev", stddev},
          {"chi2", {{"x", chi2_x}, {"y", chi2_y}, {"endpoint", chi2_endpoint}}},
          {"endpoint", {{"x", trajectory.endpoint.x()}, {"y", trajectory.endpoint.y()}}},
          {"endpoint_stddev",
           {{"x", std::sqrt(trajectory.covariance(0, 0))},
            {"y", std::sqrt(trajectory.covariance(1, 1))}}},
          {"landmarks", landmarks},
          {"reached",
           decision.reached.empty() ? nlohmann::json(nullptr) : nlohmann::json(decision.reached)}};
}

}  // namespace

std::string DiscoveryText(const DiscoveryResult& result, double alpha) {
  std::string text =
      "accelcal discover: does the baseline explain the data?\n\n  verdict: " + result.verdict +
      "\n";
  text += "\n  what the baseline leaves (residuals against the stated noise)\n";
  text +=
      "  axis  noise ratio (von Neumann)      p   chi2/dof  Ljung-Box Q(p)       Jarque-Bera (p)\n";
  for (int k = 0; k < 2; ++k) {
    const AxisDiagnostics& a = result.axes[k];
    text += StringPrintf("  %-4s  %6.4f +- %.4f %s  %9.2g  %8.4f  %8.1f (%7.2g)  %8.2f (%.2g)\n",
                         k == 0 ? "x" : "y", a.noise.ratio, a.noise.ratio_stddev,
                         a.noise_flagged ? "(off)" : "     ", a.noise.p_value, a.chi2 / a.dof,
                         a.whiteness.q, a.whiteness.p_value, a.normality.jarque_bera,
                         a.normality.p_value);
  }
  // The largest binned residual, in its standard error: where a model term is missing.
  for (int k = 0; k < 2; ++k) {
    double worst = 0.0;
    double at = 0.0;
    for (const ResidualBin& bin : result.axes[k].bins) {
      if (bin.count > 0 && std::abs(bin.mean / bin.standard_error) > std::abs(worst)) {
        worst = bin.mean / bin.standard_error;
        at = bin.theta_center_rad;
      }
    }
    text += StringPrintf(
        "  axis %s: largest binned residual %+.1f standard errors at theta = %.2f rad (%zu bins)\n",
        k == 0 ? "x" : "y", worst, at, result.axes[k].bins.size());
  }
  text += "  endpoint: " +
          (result.landmark_note.empty() ? std::string("no landmarks") : result.landmark_note) +
          "\n";

  text += StringPrintf(
      "\n  candidates (score test, 1 dof each; Holm at alpha/2 = %g among those left at each step, "
      "the other\n"
      "  alpha/2 going to the two noise tests)\n",
      alpha / 2);
  text += "  step  effect                  delta chi2        p-value  significant\n";
  for (const CandidateScore& c : result.candidates) {
    text += StringPrintf("  %4d  %-22s %11.2f %14.3g  %s\n", c.step, Info(c.effect).name,
                         c.delta_chi2, c.p_value, c.significant ? "yes" : "");
  }
  bool dropped = false;
  for (const SelectionEvent& event : result.history)
    dropped |= event.kind == SelectionEvent::Kind::kDropped;
  if (dropped) {
    text += "\n  how the model grew (backward elimination drops what a later effect explains)\n";
    for (const SelectionEvent& event : result.history) {
      const bool added = event.kind == SelectionEvent::Kind::kAdded;
      text += StringPrintf("  %-8s %-22s delta chi2 %8.2f  p %9.3g  (run tied to %s)\n",
                           added ? "added" : "dropped", Info(event.effect).name, event.delta_chi2,
                           event.p_value, event.landmark.empty() ? "none" : event.landmark.c_str());
    }
  }
  if (!result.effects.empty()) {
    text +=
        "\n  effects (final model; delta chi2, p and BIC against the final model without the "
        "effect)\n"
        "                                  estimate       1 sigma  unit        delta chi2   "
        "p-value   delta BIC\n";
    for (const DiscoveredEffect& e : result.effects) {
      text += StringPrintf("  %-28s %+12.4e  %12.3e  %-10s %10.1f %9.2g  %10.1f\n",
                           Info(e.effect).name, e.estimate, e.stddev, Info(e.effect).unit,
                           e.delta_chi2, e.p_value, e.bic_change);
    }
    text +=
        "\n  gain: the baseline parameters in the extended model, shifted by (in the baseline's "
        "sigma)\n  ";
    const ParameterEstimate baseline = FromBaselineFit(result.baseline);
    for (const Parameter parameter : baseline.free) {
      text += StringPrintf(" %s %+.2f", Info(parameter).name,
                           (result.extended.estimate.Value(parameter) - baseline.Value(parameter)) /
                               baseline.StandardDeviation(parameter));
    }
    text += "\n";
    if (result.cross_validation.folds > 0) {
      text += StringPrintf(
          "  cross-validation (%d contiguous theta blocks): held-out mean squared whitened error "
          "%.4f baseline, "
          "%.4f extended\n",
          result.cross_validation.folds, result.cross_validation.baseline,
          result.cross_validation.extended);
    }
  }
  text += "\n  endpoint (m)            x          y     1 sigma x, y    reached";
  if (!result.tied_landmark.empty())
    text += StringPrintf("    posterior of %s", result.tied_landmark.c_str());
  text += "\n";
  for (const auto& [name, trajectory, decision] :
       {std::make_tuple("baseline", &result.baseline_trajectory, &result.baseline_decision),
        std::make_tuple("extended", &result.extended_trajectory, &result.extended_decision)}) {
    text += StringPrintf("  %-10s     %10.3f %10.3f   %6.2f, %6.2f   %-16s", name,
                         trajectory->endpoint.x(), trajectory->endpoint.y(),
                         std::sqrt(trajectory->covariance(0, 0)),
                         std::sqrt(trajectory->covariance(1, 1)),
                         decision->reached.empty() ? "none consistent" : decision->reached.c_str());
    if (const LandmarkScore* score = Tied(*decision, result.tied_landmark))
      text += StringPrintf(" %.3g", score->posterior);
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
    history.push_back({{"change", event.kind == SelectionEvent::Kind::kAdded ? "added" : "dropped"},
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
  }
  nlohmann::json shifts = nlohmann::json::object();
  const ParameterEstimate baseline = FromBaselineFit(result.baseline);
  for (const Parameter parameter : baseline.free) {
    shifts[Info(parameter).name] =
        (result.extended.estimate.Value(parameter) - baseline.Value(parameter)) /
        baseline.StandardDeviation(parameter);
  }
  const LandmarkScore* before = Tied(result.baseline_decision, result.tied_landmark);
  const LandmarkScore* after = Tied(result.extended_decision, result.tied_landmark);
  return {{"problem", "discover"},
          {"alpha", alpha},
          {"verdict", result.verdict},
          {"effects", effects},
          {"effects_figures",
           "delta_chi2, p_value and delta_bic of each effect are against the final model: the "
           "chi-square the final model gains over itself without that effect, with the same "
           "landmark tie; the *_at_selection figures are those of the step that added it"},
          {"history", history},
          {"candidates", candidates},
          {"noise", noise},
          {"landmark", result.extended_decision.reached.empty()
                           ? nlohmann::json(nullptr)
                           : nlohmann::json(result.extended_decision.reached)},
          {"tied_landmark", result.tied_landmark.empty() ? nlohmann::json(nullptr)
                                                         : nlohmann::json(result.tied_landmark)},
          {"landmark_note", result.landmark_note},
          {"baseline", Side(baseline, result.baseline.chi2_x.chi2, result.baseline.chi2_y.chi2, 0.0,
                            result.baseline_trajectory, result.baseline_decision)},
          {"extended", Side(result.extended.estimate, result.extended.chi2_x,
                            result.extended.chi2_y, result.extended.chi2_endpoint,
                            result.extended_trajectory, result.extended_decision)},
          {"gain",
           {{"baseline_shift_sigma", shifts},
            {"cross_validation",
             {{"folds", result.cross_validation.folds},
              {"baseline", result.cross_validation.baseline},
              {"extended", result.cross_validation.extended}}},
            {"posterior_before", before != nullptr ? before->posterior : 0.0},
            {"posterior_after", after != nullptr ? after->posterior : 0.0}}}};
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

}  // namespace accelcal
