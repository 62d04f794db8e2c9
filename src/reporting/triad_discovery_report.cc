#include "reporting/triad_discovery_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/format.h"

namespace accelcal {

double SigmaUnderstatement(const TriadMlResult& ml, const TriadDiscoveryResult& discovery) {
  const bool understated = discovery.verdict_code == Verdict::kUnexplained &&
                           !discovery.checks.empty() && discovery.checks[0].flagged;
  return understated ? std::sqrt(std::max(ml.chi2_per_dof, 1.0)) : 1.0;
}

std::string FitDescription(const TriadMlResult& ml, bool allan_noise,
                           const TriadDiscoveryResult& discovery) {
  std::string text = StringPrintf(
      "chi2 = %.6g on %d degrees of freedom, chi2/dof = %.4g (expected 1 +- %.3g), p = "
      "P(chi2_%d > chi2) = %.3g; the pose means weighted by %s; the sigmas are "
      "ceres::Covariance's under that noise model, not scaled by chi2/dof",
      ml.chi2, ml.degrees_of_freedom, ml.chi2_per_dof, ml.chi2_per_dof_spread,
      ml.degrees_of_freedom, ml.p_value,
      allan_noise ? "the Allan variance of their samples"
                  : "white noise of the within-pose variance");
  // The factors are the reported fit's own chi2/dof (the number this sentence states), as its
  // sigmas are the ones they qualify (issue 45: a factor of another fit's, 2.3 beside a stated
  // chi2/dof of 364).
  if (allan_noise != discovery.coloured_noise) {
    text += StringPrintf(
        "; discovery weighted them by %s instead (its noise line), and the verdict is about that "
        "noise model",
        discovery.coloured_noise ? "the coloured (Allan) model" : "white noise");
  } else if (discovery.noise_overstated.flagged) {
    text += StringPrintf(
        "; the pose means scatter less than that noise model says (noted with the verdict), so "
        "the sigmas are conservative, by a factor of about %.2g",
        1.0 / std::sqrt(std::max(ml.chi2_per_dof, 1e-12)));
  } else if (discovery.verdict_code == Verdict::kUnexplained && !discovery.checks.empty() &&
             discovery.checks[0].flagged) {
    text += StringPrintf(
        "; the verdict finds the pose means scatter more than it allows, so the sigmas "
        "understate the uncertainty, by a factor of about sqrt(chi2/dof) = %.2g were the "
        "excess scatter white",
        SigmaUnderstatement(ml, discovery));
  } else if (!discovery.effects.empty() && !ml.effects_estimated.empty()) {
    text +=
        "; they are the model discovery settled on, with the effects the verdict names (the "
        "9-parameter fit beside them)";
  } else if (!discovery.effects.empty()) {
    text += "; they are the 9-parameter model's, without the effects the verdict names";
  }
  return text;
}

std::string VerdictLine(const TriadDiscoveryResult& discovery) {
  return std::string("Verdict (") + VerdictCode(discovery.verdict_code) + "): " + discovery.verdict;
}

std::string TriadDiscoveryTable(const TriadDiscoveryResult& result,
                                const TriadDiscoveryOptions& options) {
  std::ostringstream out;
  out << StringPrintf(
      "Discovery (alpha = %g: a session the 9-parameter model explains gets another verdict at "
      "most that often; docs/triad-discovery.md)\n",
      options.alpha);
  out << "  noise of the pose means: " << result.noise_note << "\n";
  out << StringPrintf("  baseline (9 parameters): chi2/dof = %.3g on %d dof, p = %.3g\n",
                      result.baseline.chi2_per_dof, result.baseline.degrees_of_freedom,
                      result.baseline.p_value);
  out << "  candidates (F test of the chi-square each removes; Holm at alpha/2 among those "
         "left):\n";
  out << StringPrintf("    %-4s %-22s %13s %10s %10s %10s  %s\n", "step", "effect", "estimate",
                      "sigma", "delta_chi2", "p", "");
  for (const TriadCandidateScore& c : result.candidates) {
    out << StringPrintf("    %-4d %-22s %13.4g %10.3g %10.3g %10.3g  %s\n", c.step, c.name.c_str(),
                        c.estimate, c.stddev, c.delta_chi2, c.p_value,
                        c.significant ? "significant" : "");
  }
  for (const TriadUntestable& u : result.untestable)
    out << "  " << u.effect << ": " << u.reason << "\n";
  if (result.effects.empty()) {
    out << "  found: none\n";
  } else {
    for (const TriadFoundEffect& e : result.effects) {
      out << StringPrintf(
          "  found: %s = %.4g +- %.2g %s (delta chi2 %.3g against the final model without it, p "
          "= %.3g)\n",
          e.name.c_str(), e.estimate, e.stddev, e.unit.c_str(), e.delta_chi2, e.p_value);
    }
  }
  out << StringPrintf("  final model: chi2/dof = %.3g on %d dof (expected 1 +- %.2g), p = %.3g\n",
                      result.final_fit.chi2_per_dof, result.final_fit.degrees_of_freedom,
                      result.final_fit.chi2_per_dof_spread, result.final_fit.p_value);
  for (const ResidualCheck& check : result.checks) {
    out << StringPrintf("  check %-22s %-14s statistic %8.3g  p = %-10.3g %s\n", check.name.c_str(),
                        ShapeClassName(check.shape_class), check.statistic, check.p_value,
                        check.flagged ? "FLAGGED" : "");
  }
  const ResidualCheck& low = result.noise_overstated;
  out << StringPrintf("  check %-22s %-14s statistic %8.3g  p = %-10.3g %s\n", low.name.c_str(),
                      ShapeClassName(low.shape_class), low.statistic, low.p_value,
                      low.flagged ? "NOTED (sigmas conservative; not part of the verdict)" : "");
  if (result.pose_wander != std::array<double, 3>{}) {
    out << "  size of what remains: a per-pose offset wander of "
        << FormatTriple(result.pose_wander, "%.3g") << " " << options.unit << " per axis\n";
  }
  for (const TriadAmbiguity& a : result.ambiguities)
    out << "  cannot tell apart: " << a.text << "\n";
  const TriadCrossValidation& cv = result.cross_validation;
  if (cv.folds > 0) {
    out << StringPrintf(
        "  leave-poses-out cross-validation (%d folds, %d poses): mean held-out chi2 per pose "
        "%.3g baseline, %.3g final model (1 for a right model)\n",
        cv.folds, cv.poses, cv.baseline, cv.final_model);
  }
  out << VerdictLine(result) << "\n";
  return out.str();
}

nlohmann::json TriadDiscoveryJson(const TriadDiscoveryResult& result,
                                  const TriadDiscoveryOptions& options) {
  nlohmann::json json;
  json["alpha"] = options.alpha;
  json["verdict"] = VerdictCode(result.verdict_code);
  json["verdict_text"] = result.verdict;
  json["noise_model"] = result.coloured_noise ? "coloured" : "white";
  json["noise_note"] = result.noise_note;
  json["baseline"] = {{"chi2", result.baseline.chi2},
                      {"dof", result.baseline.degrees_of_freedom},
                      {"p_value", result.baseline.p_value}};
  nlohmann::json candidates = nlohmann::json::array();
  for (const TriadCandidateScore& c : result.candidates) {
    candidates.push_back({{"step", c.step},
                          {"effect", c.name},
                          {"estimate", c.estimate},
                          {"stddev", c.stddev},
                          {"delta_chi2", c.delta_chi2},
                          {"p_value", c.p_value},
                          {"significant", c.significant}});
  }
  json["candidates"] = candidates;
  nlohmann::json effects = nlohmann::json::array();
  for (const TriadFoundEffect& e : result.effects) {
    effects.push_back({{"effect", e.name},
                       {"unit", e.unit},
                       {"estimate", e.estimate},
                       {"stddev", e.stddev},
                       {"delta_chi2", e.delta_chi2},
                       {"p_value", e.p_value},
                       {"step", e.step}});
  }
  json["effects"] = effects;
  nlohmann::json untestable = nlohmann::json::array();
  for (const TriadUntestable& u : result.untestable) {
    untestable.push_back({{"effect", u.effect},
                          {"confounded_with", u.confounded_with},
                          {"rank_check", u.rank_check},
                          {"reason", u.reason}});
  }
  json["untestable"] = untestable;
  json["final"] = {{"chi2", result.final_fit.chi2},
                   {"dof", result.final_fit.degrees_of_freedom},
                   {"chi2_per_dof", result.final_fit.chi2_per_dof},
                   {"chi2_per_dof_expected_spread", result.final_fit.chi2_per_dof_spread},
                   {"p_value", result.final_fit.p_value}};
  nlohmann::json checks = nlohmann::json::array();
  auto axis_of = [](const ResidualCheck& check) {
    return check.axis >= 0 && check.axis < 3 ? nlohmann::json(std::string(1, "xyz"[check.axis]))
                                             : nlohmann::json(nullptr);
  };
  for (const ResidualCheck& check : result.checks) {
    checks.push_back({{"name", check.name},
                      {"axis", axis_of(check)},
                      {"shape_class", ShapeClassName(check.shape_class)},
                      {"statistic", check.statistic},
                      {"dof", check.dof},
                      {"p_value", check.p_value},
                      {"flagged", check.flagged},
                      {"description", check.description},
                      {"advice", check.advice}});
  }
  json["checks"] = checks;
  // What remains by its shape, strongest first: the verdict's order.
  nlohmann::json shapes = nlohmann::json::array();
  for (const int i : result.remaining_checks) {
    const ResidualCheck& check = result.checks[i];
    shapes.push_back({{"check", check.name},
                      {"axis", axis_of(check)},
                      {"shape_class", ShapeClassName(check.shape_class)},
                      {"description", check.description},
                      {"advice", check.advice}});
  }
  json["remaining_shapes"] = shapes;
  json["explained_by_shape"] = result.explained_by_shape;
  const ResidualCheck& low = result.noise_overstated;
  json["noise_overstated"] = {{"name", low.name},
                              {"statistic", low.statistic},
                              {"p_value", low.p_value},
                              {"flagged", low.flagged},
                              {"description", low.description}};
  json["remaining"] = result.remaining;
  json["pose_wander"] = result.pose_wander;
  json["pose_wander_unit"] = options.unit;
  nlohmann::json ambiguities = nlohmann::json::array();
  for (const TriadAmbiguity& a : result.ambiguities) {
    ambiguities.push_back(
        {{"effect", a.effect},
         {"alternative", a.alternative},
         {"beside", a.beside},
         {"replaces", a.replaces.empty() ? nlohmann::json(nullptr) : nlohmann::json(a.replaces)},
         {"delta_chi2", a.delta_chi2},
         {"text", a.text}});
  }
  json["ambiguities"] = ambiguities;
  const TriadCrossValidation& cv = result.cross_validation;
  json["cross_validation"] = cv.folds > 0
                                 ? nlohmann::json{{"folds", cv.folds},
                                                  {"poses", cv.poses},
                                                  {"baseline_mean_heldout_chi2", cv.baseline},
                                                  {"final_mean_heldout_chi2", cv.final_model}}
                                 : nlohmann::json(nullptr);
  // Residual per pose, whitened, before (baseline) and after (final model).
  nlohmann::json before = nlohmann::json::array();
  nlohmann::json after = nlohmann::json::array();
  for (const auto& r : result.baseline.whitened_residuals) before.push_back(r);
  for (const auto& r : result.final_fit.whitened_residuals) after.push_back(r);
  json["residuals_baseline"] = before;
  json["residuals_final"] = after;
  return json;
}

}  // namespace accelcal
