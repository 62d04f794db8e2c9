#include "reporting/triad_sessions_report.h"

#include <cmath>
#include <sstream>

#include "common/format.h"
#include "models/triad.h"
#include "reporting/triad_discovery_report.h"

namespace accelcal {
namespace {

const char* Name(int p) { return TriadParameterInfos()[p].name; }

// An offset's sigma also in mm/s^2 (times the gain), the unit a user thinks of a bias in.
std::string OffsetInMps2(int p, double sigma, double gain) {
  if (TriadParameterKindOf(p) != TriadParameterKind::kOffset) return "";
  return StringPrintf(" (%.3g mm/s^2)", 1e3 * sigma * std::fabs(gain));
}

nlohmann::json ByName(const TriadParameters& values) {
  nlohmann::json json;
  for (int p = 0; p < kTriadParameterCount; ++p) json[Name(p)] = values[p];
  return json;
}

constexpr char kStddevDefinition[] =
    "within-session sigma: the sessions' mean of each one's own ceres::Covariance variance, "
    "sqrt(mean_s C_s); says how well ONE session's data determine the parameter, not how much "
    "the device moves between sessions";
constexpr char kBetweenDefinition[] =
    "tau: the standard deviation of the device's parameter from session to session beyond "
    "the within-session sigma (random-effects model theta_s = mu + delta_s + e_s, delta_s ~ "
    "N(0, tau^2), Paule-Mandel); interval: Q-profile at 95%";
constexpr char kNewSessionDefinition[] =
    "the sigma of a NEW session's estimate about `parameters` (the common value): "
    "sqrt(tau^2 + mean_s C_s + Var(common)); a 95% interval for a new session is "
    "parameters +- interval_multiplier_95 x stddev_new_session";

}  // namespace

std::string TriadSessionsTable(const TriadSessionsReport& report) {
  const int session_count = static_cast<int>(report.sessions.size());
  std::ostringstream out;
  out << StringPrintf(
      "calibrate_imu, mode ml, %d sessions of one device combined (docs/repeatability.md), g = "
      "%.10g m/s^2, outputs in %s\n",
      session_count, report.options.gravity_mps2, TriadOutputUnitName(report.options.unit));
  for (int s = 0; s < session_count; ++s) {
    const TriadSessionCalibration& calibration = report.sessions[s].calibration;
    const TriadMlResult& ml = calibration.ml;
    out << StringPrintf("session %d: %s: %d poses (noise-floor detector)\n  fit: %s\n  %s\n", s + 1,
                        report.sessions[s].path.c_str(), ml.pose_count,
                        FitDescription(ml, calibration.allan_noise, calibration.discovery).c_str(),
                        VerdictLine(calibration.discovery).c_str());
  }
  out << "\nPer session: estimate (within-session sigma), each session calibrated on its own\n";
  out << StringPrintf("  %-16s %-14s", "parameter", "unit");
  for (int s = 0; s < session_count; ++s)
    out << StringPrintf(" %25s", ("session " + std::to_string(s + 1)).c_str());
  out << "\n";
  for (int p = 0; p < kTriadParameterCount; ++p) {
    out << StringPrintf("  %-16s %-14s", Name(p),
                        TriadParameterUnit(p, report.options.unit).c_str());
    for (const TriadSessionReport& session : report.sessions) {
      out << StringPrintf(" %25s", StringPrintf("%.8g (%.2g)", session.calibration.ml.parameters[p],
                                                session.calibration.ml.stddev[p])
                                       .c_str());
    }
    out << "\n";
  }
  const RandomEffectsEstimate& first = report.combined[0];
  out << StringPrintf(
      "\nAcross sessions (random effects per parameter; %d sessions, so tau rests on %g "
      "degree(s) of freedom: its interval is wide, and a new session's 95%% interval needs "
      "t_%g(0.975) = %.3g, not 1.96)\n",
      session_count, first.between.degrees_of_freedom, first.between.degrees_of_freedom,
      first.interval_multiplier);
  out << StringPrintf("  %-16s %14s %10s %10s %10s %21s %9s %12s\n", "parameter", "common",
                      "+-sigma", "stddev", "tau", "tau 95% interval", "p(tau=0)", "new_session");
  for (int p = 0; p < kTriadParameterCount; ++p) {
    const RandomEffectsEstimate& e = report.combined[p];
    out << StringPrintf(
        "  %-16s %14.8g %10.3g %10.3g %10.3g [%9.3g, %9.3g] %9.2g %12.3g%s\n", Name(p), e.common,
        e.common_stddev, e.within_stddev, e.between.stddev, e.between.stddev_low,
        e.between.stddev_high, e.between.homogeneity_p, e.new_session_stddev,
        OffsetInMps2(p, e.new_session_stddev, report.combined[kTriadGainX + p % 3].common).c_str());
  }
  out << "  common: the device's value (weighted mean over sessions) and its sigma\n"
         "  stddev: WITHIN-session sigma, one session's own (mean over the sessions)\n"
         "  tau: BETWEEN-session sigma, how much the device moves from session to session;\n"
         "       p(tau=0): Cochran's test that the sessions agree within their own sigma\n"
         "  new_session: the sigma of a NEW session's estimate about `common`\n";
  out << StringPrintf(
      "  A new session's estimate lies, with 95%% probability, within common +- %.3g x "
      "new_session (Student t on %g dof).\n",
      first.interval_multiplier, first.between.degrees_of_freedom);
  return out.str();
}

nlohmann::json TriadSessionsJson(const TriadSessionsReport& report) {
  nlohmann::json json;
  json["mode"] = "ml_sessions";
  json["model"] =
      "a = T K (u - b), docs/triad.md, per session; random effects across sessions, "
      "docs/repeatability.md";
  json["gravity_mps2"] = report.options.gravity_mps2;
  json["output_unit"] = TriadOutputUnitName(report.options.unit);
  nlohmann::json session_units;
  for (int p = 0; p < kTriadParameterCount; ++p)
    session_units[Name(p)] = TriadParameterUnit(p, report.options.unit);
  nlohmann::json sessions = nlohmann::json::array();
  for (const TriadSessionReport& session : report.sessions) {
    const TriadMlResult& ml = session.calibration.ml;
    sessions.push_back({{"file", session.path},
                        {"units", session_units},
                        {"sha256", session.sha256},
                        {"poses", ml.pose_count},
                        {"samples", session.calibration.sample_count},
                        {"parameters", ByName(ml.parameters)},
                        {"stddev", ByName(ml.stddev)},
                        {"chi2", ml.chi2},
                        {"dof", ml.degrees_of_freedom},
                        {"chi2_per_dof", ml.chi2_per_dof},
                        {"chi2_per_dof_expected_spread", ml.chi2_per_dof_spread},
                        {"noise_model", session.calibration.allan_noise ? "allan" : "white"},
                        {"verdict", VerdictCode(session.calibration.discovery.verdict_code)},
                        {"verdict_text", session.calibration.discovery.verdict},
                        {"fit_description", FitDescription(ml, session.calibration.allan_noise,
                                                           session.calibration.discovery)},
                        {"p_value", ml.p_value}});
  }
  json["sessions"] = sessions;
  nlohmann::json parameters, common_stddev, stddev, new_session, between, interval, p_values,
      multiplier, units;
  for (int p = 0; p < kTriadParameterCount; ++p) {
    const RandomEffectsEstimate& e = report.combined[p];
    parameters[Name(p)] = e.common;
    common_stddev[Name(p)] = e.common_stddev;
    stddev[Name(p)] = e.within_stddev;
    new_session[Name(p)] = e.new_session_stddev;
    between[Name(p)] = e.between.stddev;
    interval[Name(p)] = {e.between.stddev_low, e.between.stddev_high};
    p_values[Name(p)] = e.between.homogeneity_p;
    multiplier[Name(p)] = e.interval_multiplier;
    units[Name(p)] = TriadParameterUnit(p, report.options.unit);
  }
  json["parameters"] = parameters;
  json["parameters_stddev"] = common_stddev;
  json["stddev"] = stddev;
  json["stddev_new_session"] = new_session;
  json["between_session_stddev"] = between;
  json["between_session_stddev_interval_95"] = interval;
  json["between_session_p_value"] = p_values;
  json["interval_multiplier_95"] = multiplier;
  json["degrees_of_freedom"] = report.combined[0].between.degrees_of_freedom;
  json["units"] = units;
  json["definitions"] = {
      {"parameters",
       "the device's common value: the mean of the sessions weighted by "
       "1/(tau^2 + C_s)"},
      {"parameters_stddev", "the sigma of that common value, sqrt(1 / sum_s 1/(tau^2 + C_s))"},
      {"stddev", kStddevDefinition},
      {"between_session_stddev", kBetweenDefinition},
      {"between_session_p_value",
       "P(chi2_{S-1} > Q(0)), Cochran's test that the sessions agree within their own sigma"},
      {"stddev_new_session", kNewSessionDefinition},
      {"interval_multiplier_95",
       "Student t quantile t_{S-1}(0.975): tau^2 is estimated from S sessions"}};
  return json;
}

namespace {

std::string CoverageCell(const CoverageCount& count) {
  return StringPrintf("%3d/%-3d %5.1f%%", count.covered, count.total, 100.0 * count.fraction());
}

nlohmann::json CoverageJson(const CoverageTable& table) {
  nlohmann::json json;
  for (int scheme = 0; scheme < kSessionSchemeCount; ++scheme) {
    nlohmann::json kinds;
    for (int kind = 0; kind < kTriadParameterKindCount; ++kind) {
      const CoverageCount& count = table[scheme][kind];
      kinds[TriadParameterKindName(static_cast<TriadParameterKind>(kind))] = {
          {"covered", count.covered}, {"total", count.total}, {"fraction", count.fraction()}};
    }
    json[SessionSchemeName(static_cast<SessionScheme>(scheme))] = kinds;
  }
  return json;
}

void CoverageRows(const CoverageTable& table, std::ostringstream* out) {
  *out << StringPrintf("  %-8s %18s %18s %18s\n", "scheme", "misalignment", "gain", "offset");
  for (int scheme = 0; scheme < kSessionSchemeCount; ++scheme) {
    *out << StringPrintf("  %-8s", SessionSchemeName(static_cast<SessionScheme>(scheme)));
    for (int kind = 0; kind < kTriadParameterKindCount; ++kind)
      *out << StringPrintf(" %18s", CoverageCell(table[scheme][kind]).c_str());
    *out << "\n";
  }
}

constexpr char kSchemes[] =
    "  device: each device's own tau, t on S-1 dof (what calibrate_imu --log=S1,S2,... "
    "reports)\n"
    "  pooled: tau shared by the array's devices as if independent, t on D(S-1) dof\n"
    "  array:  a session's shift common to every device plus each device's own (two-way), t on "
    "Satterthwaite's dof\n";

}  // namespace

std::string RepeatabilityMonteCarloTable(const RepeatabilityMonteCarloResult& result) {
  const RepeatabilityMonteCarloOptions& o = result.options;
  std::ostringstream out;
  out << StringPrintf(
      "Monte Carlo: %d simulated arrays of %d mimu4444-like triads, %d training sessions + 1 "
      "new, %d poses of %d samples, noise %.3g/%.3g/%.3g counts, seed %llu; %d failed trials\n",
      o.trials, o.devices, o.training_sessions, o.poses, o.samples_per_pose, o.noise_stddev[0],
      o.noise_stddev[1], o.noise_stddev[2], static_cast<unsigned long long>(o.seed),
      result.failed_trials);
  out << "  true between-session sigma (common share):";
  for (int p = 0; p < kTriadParameterCount; ++p)
    out << StringPrintf(" %s %.2g (%.2f)", Name(p), o.between_stddev[p], o.common_share[p]);
  out << "\n  coverage of the new session by the 95% interval (standard error "
      << StringPrintf("%.1f%% on %d independent arrays):\n", 100.0 * result.coverage_standard_error,
                      o.trials - result.failed_trials);
  CoverageRows(result.coverage, &out);
  out << "  device scheme's 95% interval of tau covering the true sigma, and mean tau^2 / true:\n";
  for (int kind = 0; kind < kTriadParameterKindCount; ++kind) {
    out << StringPrintf(
        "    %-12s %s   %.3g\n", TriadParameterKindName(static_cast<TriadParameterKind>(kind)),
        CoverageCell(result.tau_interval_coverage[kind]).c_str(), result.tau2_ratio[kind]);
  }
  return out.str();
}

nlohmann::json RepeatabilityMonteCarloJson(const RepeatabilityMonteCarloResult& result) {
  const RepeatabilityMonteCarloOptions& o = result.options;
  nlohmann::json tau;
  for (int kind = 0; kind < kTriadParameterKindCount; ++kind) {
    const CoverageCount& count = result.tau_interval_coverage[kind];
    tau[TriadParameterKindName(static_cast<TriadParameterKind>(kind))] = {
        {"interval_coverage", count.fraction()},
        {"total", count.total},
        {"mean_tau2_over_truth", result.tau2_ratio[kind]}};
  }
  return {{"trials", o.trials},
          {"failed_trials", result.failed_trials},
          {"devices", o.devices},
          {"training_sessions", o.training_sessions},
          {"poses", o.poses},
          {"samples_per_pose", o.samples_per_pose},
          {"noise_stddev", o.noise_stddev},
          {"seed", o.seed},
          {"between_session_stddev", ByName(o.between_stddev)},
          {"common_share", ByName(o.common_share)},
          {"coverage", CoverageJson(result.coverage)},
          {"coverage_standard_error", result.coverage_standard_error},
          {"tau", tau}};
}

std::string TriadRepeatabilityTable(const TriadRepeatabilityReport& report) {
  const size_t device_count = report.device_names.size();
  const size_t session_count = report.session_names.size();
  std::ostringstream out;
  out << StringPrintf(
      "triad_repeatability: %zu devices x %zu sessions, each session calibrated on its own "
      "(mode ml, noise-floor detector), g = %.10g m/s^2 (docs/repeatability.md)\n\n",
      device_count, session_count, report.gravity_mps2);
  for (int p = 0; p < kTriadParameterCount; ++p) {
    out << StringPrintf(
        "%s (%s): per session estimate (within-session sigma); device: tau "
        "[95%%], new-session sigma\n",
        Name(p), TriadParameterInfos()[p].unit);
    for (size_t d = 0; d < device_count; ++d) {
      out << StringPrintf("  %-6s", report.device_names[d].c_str());
      for (size_t s = 0; s < session_count; ++s) {
        const TriadMlResult& ml = report.sessions[d][s];
        out << StringPrintf(" %24s",
                            StringPrintf("%.7g (%.2g)", ml.parameters[p], ml.stddev[p]).c_str());
      }
      const RandomEffectsEstimate& e = report.per_device[d][p];
      const double gain = report.per_device[d][kTriadGainX + (p % 3)].common;
      out << StringPrintf("   tau %.3g [%.2g, %.2g]%s  new %.3g\n", e.between.stddev,
                          e.between.stddev_low, e.between.stddev_high,
                          OffsetInMps2(p, e.between.stddev, gain).c_str(), e.new_session_stddev);
    }
    const ArraySessionVariance& a = report.array[p];
    out << StringPrintf(
        "  array: between-session sigma %.3g (common to all devices %.3g, own %.3g; common "
        "share %.2f), new-session sigma %.3g on %.2f dof\n\n",
        std::sqrt(a.common_variance + a.device_variance), std::sqrt(a.common_variance),
        std::sqrt(a.device_variance), a.common_share,
        std::sqrt(a.total_variance * (1.0 + 1.0 / session_count)), a.degrees_of_freedom);
  }
  out << StringPrintf(
      "Leave one session out: each of the %zu sessions predicted from the other %zu, every "
      "device and parameter; covered when inside the 95%% interval\n",
      session_count, session_count - 1);
  out << kSchemes;
  out << "  claimed: device (what calibrate_imu reports). pooled and array borrow strength from "
         "the\n"
         "  other devices, which a session shift shared by the whole array defeats: both "
         "under-cover\n"
         "  the offsets in the Monte Carlo (docs/repeatability.md)\n";
  CoverageRows(report.loso.coverage, &out);
  out << "  by held-out session (all kinds):";
  for (int scheme = 0; scheme < kSessionSchemeCount; ++scheme) {
    out << StringPrintf("  %s", SessionSchemeName(static_cast<SessionScheme>(scheme)));
    for (size_t s = 0; s < session_count; ++s) {
      const CoverageCount& c = report.loso.coverage_by_session[scheme][s];
      out << StringPrintf(" %s %d/%d", report.session_names[s].c_str(), c.covered, c.total);
    }
  }
  out << "\n";
  if (report.has_monte_carlo) out << "\n" << RepeatabilityMonteCarloTable(report.monte_carlo);
  return out.str();
}

nlohmann::json TriadRepeatabilityJson(const TriadRepeatabilityReport& report) {
  nlohmann::json json;
  json["gravity_mps2"] = report.gravity_mps2;
  json["devices"] = report.device_names;
  json["session_names"] = report.session_names;
  nlohmann::json devices = nlohmann::json::array();
  for (size_t d = 0; d < report.device_names.size(); ++d) {
    nlohmann::json sessions = nlohmann::json::array();
    for (const TriadMlResult& ml : report.sessions[d]) {
      sessions.push_back({{"parameters", ByName(ml.parameters)},
                          {"stddev", ByName(ml.stddev)},
                          {"poses", ml.pose_count},
                          {"chi2_per_dof", ml.chi2_per_dof}});
    }
    TriadParameters common{}, within{}, tau{}, new_session{};
    for (int p = 0; p < kTriadParameterCount; ++p) {
      const RandomEffectsEstimate& e = report.per_device[d][p];
      common[p] = e.common;
      within[p] = e.within_stddev;
      tau[p] = e.between.stddev;
      new_session[p] = e.new_session_stddev;
    }
    devices.push_back({{"name", report.device_names[d]},
                       {"sessions", sessions},
                       {"parameters", ByName(common)},
                       {"stddev", ByName(within)},
                       {"between_session_stddev", ByName(tau)},
                       {"stddev_new_session", ByName(new_session)},
                       {"interval_multiplier_95", report.per_device[d][0].interval_multiplier}});
  }
  json["per_device"] = devices;
  nlohmann::json array;
  for (int p = 0; p < kTriadParameterCount; ++p) {
    const ArraySessionVariance& a = report.array[p];
    array[Name(p)] = {{"between_session_stddev", std::sqrt(a.common_variance + a.device_variance)},
                      {"common_stddev", std::sqrt(a.common_variance)},
                      {"device_stddev", std::sqrt(a.device_variance)},
                      {"common_share", a.common_share},
                      {"degrees_of_freedom", a.degrees_of_freedom}};
  }
  json["array"] = array;
  json["leave_one_session_out"] = {{"coverage", CoverageJson(report.loso.coverage)},
                                   {"confidence", 0.95}};
  if (report.has_monte_carlo) json["monte_carlo"] = RepeatabilityMonteCarloJson(report.monte_carlo);
  return json;
}

}  // namespace accelcal
