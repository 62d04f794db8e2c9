#include "reporting/triad_study_report.h"

#include <cmath>

#include "common/format.h"

namespace accelcal {
namespace {

std::string Header(const TriadStudyReport& report) {
  const TriadMonteCarloOptions& o = report.options;
  const TriadMonteCarloResult& r = report.result;
  std::string text = StringPrintf(
      "triad_study: the maximum-likelihood triad calibration (%d parameters) on %d simulated "
      "sessions of the same %zu poses (pose set %s)\n",
      r.parameter_count, o.trials, r.directions.size(), TriadPoseSetName(o.pose_set));
  text += StringPrintf(
      "  %d samples per pose, white noise sd %s counts per sample, g = %s m/s^2; the fit starts "
      "from angles 0, k2 0, gains and offsets at the mean of the truth's three\n",
      o.samples_per_pose, FormatTriple(o.noise_stddev, "%g").c_str(),
      RoundTripDouble(o.gravity_mps2).c_str());
  const bool k2_simulated = o.truth_scale_nonlinearity != TriadScaleNonlinearity{};
  if (k2_simulated) {
    text += StringPrintf("  simulated scale_nonlinearity %s 1/(m/s^2)%s\n",
                         FormatTriple(o.truth_scale_nonlinearity).c_str(),
                         o.scale_nonlinearity ? "" : ", NOT in the fitted model");
  }
  return text;
}

std::string RefusalText(const TriadMonteCarloResult& r) {
  std::string text = "\nrefused: the calibration of the first session says:\n  " + r.refusal + "\n";
  if (!r.unidentifiable.empty())
    text += "  unidentifiable: " + JoinStrings(r.unidentifiable) + "\n";
  if (!r.suggested_directions.empty()) {
    text += "  poses to add (unit specific force, sensor frame, pointing up when held still):";
    for (const auto& d : r.suggested_directions) text += " " + FormatTriple(d, "%.2f");
    text += "\n";
  }
  text += "  (no trials run: a pose set the calibration refuses has no sigma to check)\n";
  return text;
}

std::string VerdictText(const TriadMonteCarloResult& r) {
  std::string text;
  if (r.passed) {
    text = StringPrintf(
        "verdict: %s: every reported sigma within [0.9, 1.1] of the Monte Carlo spread (or 3 "
        "sd of the ratio, when wider), every "
        "coverage at 1, 2, 3 sigma and the p < 0.01 rate within 3 binomial sd of the expected, "
        "%d of %d trials fitted",
        r.claim_possible ? "PASS" : "consistent, but no claim (fewer than 1000 trials)",
        r.trials_ok, r.trials_ok + r.trials_failed);
    return text + "\n";
  }
  text = StringPrintf("verdict: FAIL (%zu check%s):\n", r.failures.size(),
                      r.failures.size() == 1 ? "" : "s");
  for (const std::string& failure : r.failures) text += "  " + failure + "\n";
  return text;
}

std::string Table(const TriadMonteCarloResult& r) {
  std::string text = StringPrintf("\n  %-20s %-13s %13s %13s %7s %10s %10s %14s  %5s %5s %5s\n",
                                  "parameter", "unit", "truth", "mean", "bias/s", "MC spread",
                                  "mean sigma", "sigma/spread", "1s%", "2s%", "3s%");
  for (const TriadParameterStudy& row : r.parameters) {
    text += StringPrintf(
        "  %-20s %-13s %13.8g %13.8g %+7.3f %10.4g %10.4g %7.3f +-%.3f  %5.1f %5.1f %5.1f\n",
        row.name.c_str(), row.unit.c_str(), row.truth, row.mean, row.bias_sigma, row.spread,
        row.mean_sigma, row.ratio, row.ratio_stderr, 100.0 * row.coverage[0],
        100.0 * row.coverage[1], 100.0 * row.coverage[2]);
  }
  const int n = std::max(r.trials_ok, 1);
  std::string expected;
  for (int level = 0; level < 3; ++level) {
    const double p = TriadMonteCarloResult::kExpectedCoverage[level];
    expected += StringPrintf("%s%.1f +- %.1f", level == 0 ? "" : ", ", 100.0 * p,
                             100.0 * 3.0 * std::sqrt(p * (1.0 - p) / n));
  }
  text += StringPrintf(
      "  (bias/s: (mean - truth) / mean sigma, sd %.3f; sigma/spread +- its sd 1/sqrt(2(N-1)), "
      "verdict band [0.9, 1.1];\n   coverage: truth within 1, 2, 3 reported sigma, expected "
      "%s%% (3 sd); N = %d trials)\n",
      1.0 / std::sqrt(static_cast<double>(n)), expected.c_str(), r.trials_ok);
  text += StringPrintf(
      "\n  fit statistic: chi2/dof on %d dof, mean %.4f (expected 1 +- %.4f); p < 0.01 in %.1f%% "
      "of trials (expected 1.0%% +- %.1f%%, 3 sd)\n",
      r.degrees_of_freedom, r.chi2_per_dof_mean, r.chi2_per_dof_mean_stderr, 100.0 * r.p_below_001,
      100.0 * 3.0 * r.p_below_001_stderr);
  return text;
}

nlohmann::json Directions(const std::vector<std::array<double, 3>>& directions) {
  nlohmann::json json = nlohmann::json::array();
  for (const auto& d : directions) json.push_back({d[0], d[1], d[2]});
  return json;
}

}  // namespace

std::string TriadStudyText(const TriadStudyReport& report) {
  const TriadMonteCarloResult& r = report.result;
  std::string text = Header(report);
  if (r.refused) return text + RefusalText(r);
  text += "\n" + VerdictText(r) + Table(r);
  text += StringPrintf("\n  %d trials in %.1f s on %d thread%s\n", r.trials_ok + r.trials_failed,
                       r.seconds, r.threads, r.threads == 1 ? "" : "s");
  return text;
}

nlohmann::json TriadStudyJson(const TriadStudyReport& report) {
  const TriadMonteCarloOptions& o = report.options;
  const TriadMonteCarloResult& r = report.result;
  nlohmann::json truth = nlohmann::json::object();
  for (int p = 0; p < kTriadParameterCount; ++p) truth[TriadParameterInfos()[p].name] = o.truth[p];
  for (int k = 0; k < kTriadScaleNonlinearityCount; ++k)
    truth[TriadScaleNonlinearityInfos()[k].name] = o.truth_scale_nonlinearity[k];
  nlohmann::json json = {
      {"problem", "triad_study"},
      {"options",
       {{"trials", o.trials},
        {"seed", o.seed},
        {"pose_set", TriadPoseSetName(o.pose_set)},
        {"poses", r.directions.size()},
        {"samples_per_pose", o.samples_per_pose},
        {"noise_stddev_counts", {o.noise_stddev[0], o.noise_stddev[1], o.noise_stddev[2]}},
        {"gravity_mps2", o.gravity_mps2},
        {"scale_nonlinearity", o.scale_nonlinearity},
        {"truth", truth}}},
      {"parameter_count", r.parameter_count},
      {"directions", Directions(r.directions)},
      {"refused", r.refused},
  };
  // Both outcomes write every key; what does not apply to one is null (docs/json.md).
  json["refusal"] = r.refused ? nlohmann::json(r.refusal) : nlohmann::json(nullptr);
  json["unidentifiable"] = r.refused ? nlohmann::json(r.unidentifiable) : nlohmann::json(nullptr);
  json["suggested_directions"] =
      r.refused ? Directions(r.suggested_directions) : nlohmann::json(nullptr);
  if (r.refused) {
    for (const char* key : {"rows", "expected_coverage", "fit_statistic", "first_failure",
                            "verdict", "seconds", "threads"}) {
      json[key] = nullptr;
    }
    json["trials_ok"] = 0;  // counts: no session was simulated
    json["trials_failed"] = 0;
    return json;
  }
  nlohmann::json rows = nlohmann::json::array();
  for (const TriadParameterStudy& row : r.parameters) {
    rows.push_back(
        {{"name", row.name},
         {"unit", row.unit},
         {"truth", row.truth},
         {"mean", row.mean},
         {"bias_sigma", row.bias_sigma},
         {"bias_sigma_stderr", row.bias_sigma_stderr},
         {"spread", row.spread},
         {"mean_sigma", row.mean_sigma},
         {"ratio", row.ratio},
         {"ratio_stderr", row.ratio_stderr},
         {"coverage", {{"1", row.coverage[0]}, {"2", row.coverage[1]}, {"3", row.coverage[2]}}}});
  }
  json["rows"] = rows;
  json["expected_coverage"] = {{"1", TriadMonteCarloResult::kExpectedCoverage[0]},
                               {"2", TriadMonteCarloResult::kExpectedCoverage[1]},
                               {"3", TriadMonteCarloResult::kExpectedCoverage[2]}};
  json["fit_statistic"] = {{"dof", r.degrees_of_freedom},
                           {"chi2_per_dof_mean", r.chi2_per_dof_mean},
                           {"chi2_per_dof_mean_stderr", r.chi2_per_dof_mean_stderr},
                           {"p_below_0_01", r.p_below_001},
                           {"p_below_0_01_stderr", r.p_below_001_stderr}};
  json["trials_ok"] = r.trials_ok;
  json["trials_failed"] = r.trials_failed;
  json["first_failure"] =
      r.trials_failed > 0 ? nlohmann::json(r.first_failure) : nlohmann::json(nullptr);
  json["verdict"] = {
      {"claim_possible", r.claim_possible}, {"passed", r.passed}, {"failures", r.failures}};
  json["seconds"] = r.seconds;
  json["threads"] = r.threads;
  return json;
}

}  // namespace accelcal
