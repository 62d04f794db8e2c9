#include "reporting/gyroscope_study_report.h"

#include <algorithm>
#include <sstream>

#include "common/format.h"

namespace accelcal {
namespace {

std::string StudyVerdict(const GyroscopeMonteCarloResult& result) {
  if (result.refused) return "REFUSED (the design does not determine the gyroscope)";
  if (!result.passed) return "FAIL";
  return result.claim_possible ? "PASS" : "PASS (fewer than 1000 trials: no claim)";
}

}  // namespace

std::string GyroscopeStudyText(const GyroscopeStudyReport& report) {
  const GyroscopeMonteCarloOptions& options = report.options;
  const GyroscopeSessionDesign& design = options.design;
  const GyroscopeMonteCarloResult& result = report.result;
  std::ostringstream out;
  out << StringPrintf(
      "gyroscope_study: %d simulated hand-held sessions of %d poses (%s turns, %.3g s holds, "
      "%.3g s turns at %.4g Hz), gyroscope noise %.3g, %.3g, %.3g counts per sample, "
      "accelerometer %.3g counts; seed %llu\n",
      result.trials, design.poses, GyroscopeTurnSetName(design.turn_set), design.hold_s,
      design.turn_s, design.rate_hz, design.gyroscope_noise[0], design.gyroscope_noise[1],
      design.gyroscope_noise[2], design.accelerometer_noise[0],
      static_cast<unsigned long long>(options.seed));
  if (result.refused) {
    out << "refused: " << result.refusal << "\n";
    out << "verdict: " << StudyVerdict(result) << "\n";
    return out.str();
  }
  out << StringPrintf("%d of %d trials calibrated (%.1f s)\n\n", result.succeeded, result.trials,
                      result.seconds);
  out << StringPrintf("%-36s %13s %13s %8s %11s %11s %7s  %s\n", "unknown", "truth", "mean",
                      "bias/sd", "spread", "mean sigma", "ratio", "within 1/2/3 sigma (%)");
  for (const GyroscopeUnknownStudy& row : result.unknowns) {
    out << StringPrintf("%-36s %13.6g %13.6g %+8.2f %11.4g %11.4g %7.3f  %.1f/%.1f/%.1f%s\n",
                        (row.name + " [" + row.unit + "]").c_str(), row.truth, row.mean,
                        row.bias_sigma, row.spread, row.mean_sigma, row.ratio,
                        100.0 * row.coverage[0], 100.0 * row.coverage[1], 100.0 * row.coverage[2],
                        row.ratio_ok && row.coverage_ok ? "" : "  <-");
  }
  out << StringPrintf(
      "\nfit statistic (what the gyroscope adds to the accelerometer's chi2): mean chi2/dof %.3f, "
      "p < 0.01 "
      "in %.2f%% of trials (expected 1%%)\n",
      result.mean_chi2_per_dof, 100.0 * result.p_below_001);
  out << "expected: ratio in [0.9, 1.1], coverage 68.3/95.4/99.7% within 3 binomial sd\n";
  if (options.discovery_alpha > 0.0) {
    const double n = std::max(1, result.succeeded);
    out << StringPrintf(
        "discovery at alpha = %g: explained %.1f%%, missing %.1f%%, unexplained %.1f%%, cannot "
        "tell apart %.1f%% of %d sessions",
        options.discovery_alpha, 100.0 * result.verdicts[0] / n, 100.0 * result.verdicts[1] / n,
        100.0 * result.verdicts[2] / n, 100.0 * result.verdicts[3] / n, result.succeeded);
    for (int e = 0; e < kGyroscopeEffectCount; ++e) {
      if (GyroscopeEffectInfos()[e].not_a_candidate != nullptr) continue;
      out << StringPrintf("; %s found in %.1f%%", GyroscopeEffectInfos()[e].name,
                          100.0 * result.found[e] / n);
    }
    out << "\n";
    out << "what-remains checks flagged:";
    if (result.checks_flagged.empty()) out << " none";
    for (const auto& [check, count] : result.checks_flagged)
      out << StringPrintf(" %s %.1f%%", check.c_str(), 100.0 * count / n);
    out << "\n";
  }
  for (const std::string& failure : result.failures) out << "  " << failure << "\n";
  out << "verdict: " << StudyVerdict(result) << "\n";
  return out.str();
}

nlohmann::json GyroscopeStudyJson(const GyroscopeStudyReport& report) {
  const GyroscopeMonteCarloOptions& options = report.options;
  const GyroscopeSessionDesign& design = options.design;
  const GyroscopeMonteCarloResult& result = report.result;
  nlohmann::json json;
  json["problem"] = "gyroscope_study";
  json["design"] = {{"turn_set", GyroscopeTurnSetName(design.turn_set)},
                    {"poses", design.poses},
                    {"hold_s", design.hold_s},
                    {"turn_s", design.turn_s},
                    {"rate_hz", design.rate_hz},
                    {"gravity_mps2", design.gravity_mps2},
                    {"gyroscope_noise_counts", design.gyroscope_noise},
                    {"accelerometer_noise_counts", design.accelerometer_noise},
                    {"trials", options.trials},
                    {"seed", options.seed}};
  json["refused"] = result.refused;
  json["refusal"] = result.refused ? nlohmann::json(result.refusal) : nlohmann::json(nullptr);
  json["undetermined"] = result.undetermined;
  json["turn_axes_to_add"] = result.turn_axes_to_add;
  json["trials_succeeded"] = result.succeeded;
  nlohmann::json unknowns = nlohmann::json::array();
  for (const GyroscopeUnknownStudy& row : result.unknowns) {
    unknowns.push_back({{"name", row.name},
                        {"unit", row.unit},
                        {"truth", row.truth},
                        {"mean", row.mean},
                        {"bias_sigmas", row.bias_sigma},
                        {"spread", row.spread},
                        {"mean_sigma", row.mean_sigma},
                        {"ratio", row.ratio},
                        {"coverage", row.coverage},
                        {"ratio_ok", row.ratio_ok},
                        {"coverage_ok", row.coverage_ok}});
  }
  json["unknowns"] = unknowns;
  json["fit_statistic"] = {{"mean_chi2_per_dof", result.mean_chi2_per_dof},
                           {"p_below_0.01", result.p_below_001},
                           {"ok", result.p_ok}};
  if (options.discovery_alpha > 0.0) {
    nlohmann::json found;
    for (int e = 0; e < kGyroscopeEffectCount; ++e)
      if (GyroscopeEffectInfos()[e].not_a_candidate == nullptr)
        found[GyroscopeEffectInfos()[e].name] = result.found[e];
    nlohmann::json checks = nlohmann::json::object();
    for (const auto& [check, count] : result.checks_flagged) checks[check] = count;
    json["discovery"] = {{"alpha", options.discovery_alpha},
                         {"checks_flagged", checks},
                         {"verdicts",
                          {{"explained", result.verdicts[0]},
                           {"missing", result.verdicts[1]},
                           {"unexplained", result.verdicts[2]},
                           {"cannot_tell_apart", result.verdicts[3]}}},
                         {"found", found},
                         {"null_rate_ok", result.null_rate_ok}};
  } else {
    json["discovery"] = nullptr;
  }
  json["failures"] = result.failures;
  json["verdict"] = StudyVerdict(result);
  json["seconds"] = result.seconds;
  return json;
}

}  // namespace accelcal
