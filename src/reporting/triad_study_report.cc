#include "reporting/triad_study_report.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "common/format.h"
#include "estimation/discovery/verdict.h"

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

std::string TriadDiscoveryStudyText(const TriadDiscoveryStudyOptions& options,
                                    const TriadDiscoveryStudyResult& result) {
  std::string text = StringPrintf(
      "Discovery on %d simulated sessions (seed %llu): %d poses of %.3g s, turns of %.3g s, "
      "%.4g Hz, outputs rounded to counts\n"
      "  white noise per sample (%.3g, %.3g, %.3g) counts\n",
      options.sessions, static_cast<unsigned long long>(options.seed), options.poses,
      options.hold_s, options.turn_s, options.rate_hz, options.noise_stddev[0],
      options.noise_stddev[1], options.noise_stddev[2]);
  if (options.flicker_b != std::array<double, 3>{}) {
    text += StringPrintf(
        "  flicker noise B = (%.3g, %.3g, %.3g) counts (Allan deviation floor 0.664 B), a bank "
        "of Gauss-Markov processes at correlation times %.3g to %.3g s\n",
        options.flicker_b[0], options.flicker_b[1], options.flicker_b[2], options.flicker_min_s,
        options.flicker_max_s);
  } else {
    text += "  no flicker noise\n";
  }
  if (options.offset_drift != std::array<double, 3>{}) {
    text += StringPrintf("  offset drift (%.3g, %.3g, %.3g) counts/s (hidden)\n",
                         options.offset_drift[0], options.offset_drift[1], options.offset_drift[2]);
  }
  text += StringPrintf("  alpha %.3g\n\n", options.alpha);
  text += StringPrintf(
      "sessions calibrated: %d (failed %d%s%s)\n", result.sessions_ok, result.sessions_failed,
      result.first_failure.empty() ? "" : "; first: ", result.first_failure.c_str());
  text +=
      StringPrintf("verdicts: explained %d, missing %d, unexplained %d, cannot_tell_apart %d\n",
                   result.verdicts[0], result.verdicts[1], result.verdicts[2], result.verdicts[3]);
  text += StringPrintf(
      "coloured noise model chosen: %d; an effect named: %d; something "
      "remained: %d; final chi2/dof mean %.3f\n",
      result.coloured_noise, result.effect_named, result.unexplained, result.mean_chi2_per_dof);
  text += StringPrintf(
      "Allan terms of the poses, mean: N (%.3g, %.3g, %.3g) count/sqrt(Hz), B (%.3g, %.3g, %.3g) "
      "counts, K (%.3g, %.3g, %.3g) count sqrt(Hz)\n",
      result.mean_fitted_n[0], result.mean_fitted_n[1], result.mean_fitted_n[2],
      result.mean_fitted_b[0], result.mean_fitted_b[1], result.mean_fitted_b[2],
      result.mean_fitted_k[0], result.mean_fitted_k[1], result.mean_fitted_k[2]);
  text += StringPrintf("offset_drift found: x %d, y %d, z %d\n", result.drift_found[0],
                       result.drift_found[1], result.drift_found[2]);
  const double n = std::max(result.sessions_ok, 1);
  const bool hidden = options.offset_drift != std::array<double, 3>{};
  text += StringPrintf(
      "beyond the noise (an effect named, unexplained or cannot_tell_apart): %d of %d = %.4f; %s",
      result.beyond_noise, result.sessions_ok, result.beyond_noise / n,
      hidden ? "an effect is hidden, so this is power, not the level\n"
             : StringPrintf("with nothing hidden it should be <= alpha + 2 sd = %.4f: %s\n",
                            result.level_band, result.level_held ? "level held" : "LEVEL NOT HELD")
                   .c_str());
  text += StringPrintf("%.1f s on %d threads\n", result.seconds, result.threads);
  return text;
}

nlohmann::json TriadDiscoveryStudyJson(const TriadDiscoveryStudyOptions& options,
                                       const TriadDiscoveryStudyResult& result) {
  nlohmann::json json;
  json["problem"] = "triad_study";
  json["study"] = "discovery";
  json["options"] = {{"sessions", options.sessions},
                     {"seed", options.seed},
                     {"poses", options.poses},
                     {"hold_s", options.hold_s},
                     {"turn_s", options.turn_s},
                     {"rate_hz", options.rate_hz},
                     {"noise_stddev_counts", options.noise_stddev},
                     {"flicker_b_counts", options.flicker_b},
                     {"flicker_band_s", {options.flicker_min_s, options.flicker_max_s}},
                     {"offset_drift_counts_per_s", options.offset_drift},
                     {"alpha", options.alpha},
                     {"g_mps2", options.gravity_mps2}};
  json["sessions_ok"] = result.sessions_ok;
  json["sessions_failed"] = result.sessions_failed;
  json["first_failure"] = result.first_failure;
  json["verdicts"] = nlohmann::json::object();
  for (const Verdict verdict :
       {Verdict::kExplained, Verdict::kMissing, Verdict::kUnexplained, Verdict::kCannotTellApart})
    json["verdicts"][VerdictCode(verdict)] = result.verdicts[static_cast<int>(verdict)];
  json["coloured_noise"] = result.coloured_noise;
  json["effect_named"] = result.effect_named;
  json["unexplained"] = result.unexplained;
  json["beyond_noise"] = result.beyond_noise;
  json["beyond_noise_rate"] = result.beyond_noise_rate;
  json["level_band"] = result.level_band;
  json["level_held"] = result.level_held;
  json["offset_drift_found"] = result.drift_found;
  json["mean_final_chi2_per_dof"] = result.mean_chi2_per_dof;
  json["mean_fitted_allan_b_counts"] = result.mean_fitted_b;
  json["seconds"] = result.seconds;
  json["threads"] = result.threads;
  return json;
}

}  // namespace accelcal
