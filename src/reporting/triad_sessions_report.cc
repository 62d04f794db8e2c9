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

namespace {

// One sensor's parameters as the sessions tables print them: names, units, and per parameter
// and session the estimate and its within-session sigma.
struct SessionRows {
  std::vector<std::string> names;
  std::vector<std::string> units;
  std::vector<std::vector<double>> values;   // [p][s]
  std::vector<std::vector<double>> stddevs;  // [p][s]
  std::vector<int> session_numbers;          // the columns' sessions, from 1
  int name_width = 16;
};

SessionRows TriadRows(const TriadSessionsReport& report) {
  SessionRows rows;
  for (int p = 0; p < kTriadParameterCount; ++p) {
    rows.names.push_back(Name(p));
    rows.units.push_back(TriadParameterUnit(p, report.options.unit));
    rows.values.emplace_back();
    rows.stddevs.emplace_back();
    for (const TriadSessionReport& session : report.sessions) {
      rows.values[p].push_back(session.calibration.ml.parameters[p]);
      rows.stddevs[p].push_back(session.calibration.ml.stddev[p]);
    }
  }
  for (size_t s = 0; s < report.sessions.size(); ++s)
    rows.session_numbers.push_back(static_cast<int>(s) + 1);
  return rows;
}

SessionRows GyroscopeRows(const TriadSessionsReport& report) {
  SessionRows rows;
  rows.name_width = 26;
  for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
    rows.names.push_back(GyroscopeCalibrationParameterName(i));
    rows.units.push_back(GyroscopeParameterUnit(i, report.gyroscope_options.session.unit));
    rows.values.emplace_back();
    rows.stddevs.emplace_back();
    for (int s : report.gyroscope.sessions) {
      const GyroscopeMlResult& ml = report.sessions[s].gyroscope.calibration.ml;
      rows.values[i].push_back(i < kGyroscopeOffsetX ? ml.parameters[i]
                                                     : ml.offset[i - kGyroscopeOffsetX]);
      rows.stddevs[i].push_back(ml.stddev[i]);
    }
  }
  for (int s : report.gyroscope.sessions) rows.session_numbers.push_back(s + 1);
  return rows;
}

void PerSessionTable(const SessionRows& rows, std::ostringstream* out) {
  *out << StringPrintf("  %-*s %-14s", rows.name_width, "parameter", "unit");
  for (int number : rows.session_numbers)
    *out << StringPrintf(" %25s", ("session " + std::to_string(number)).c_str());
  *out << "\n";
  for (size_t p = 0; p < rows.names.size(); ++p) {
    *out << StringPrintf("  %-*s %-14s", rows.name_width, rows.names[p].c_str(),
                         rows.units[p].c_str());
    for (size_t s = 0; s < rows.values[p].size(); ++s) {
      *out << StringPrintf(
          " %25s", StringPrintf("%.8g (%.2g)", rows.values[p][s], rows.stddevs[p][s]).c_str());
    }
    *out << "\n";
  }
}

// `suffixes[p]`: what follows parameter p's new-session sigma (an offset's in a physical unit).
void AcrossSessionsTable(const SessionRows& rows,
                         const std::vector<RandomEffectsEstimate>& combined,
                         const std::vector<std::string>& suffixes, std::ostringstream* out) {
  *out << StringPrintf("  %-*s %14s %10s %10s %10s %21s %9s %12s\n", rows.name_width, "parameter",
                       "common", "+-sigma", "stddev", "tau", "tau 95% interval", "p(tau=0)",
                       "new_session");
  for (size_t p = 0; p < rows.names.size(); ++p) {
    const RandomEffectsEstimate& e = combined[p];
    *out << StringPrintf("  %-*s %14.8g %10.3g %10.3g %10.3g [%9.3g, %9.3g] %9.2g %12.3g%s\n",
                         rows.name_width, rows.names[p].c_str(), e.common, e.common_stddev,
                         e.within_stddev, e.between.stddev, e.between.stddev_low,
                         e.between.stddev_high, e.between.homogeneity_p, e.new_session_stddev,
                         suffixes[p].c_str());
  }
}

constexpr char kDriftRule[] =
    "a session is named when some parameter lies outside the interval the OTHER sessions give a "
    "new session (leave one out, their own tau) at confidence 1 - level/P, P the sensor's "
    "parameter count (Bonferroni): a session drawn like the others is named with probability at "
    "most `level`";

// `names`: the sensor's parameters; `session_numbers[i]`: the session (from 1) of the check's
// i-th session.
void DriftLines(const char* sensor, const SessionDriftCheck& check,
                const std::vector<std::string>& names, const std::vector<int>& session_numbers,
                std::ostringstream* out) {
  if (!check.checked) {
    *out << StringPrintf("Drift (%s): not checked: %s\n", sensor, check.not_checked.c_str());
    return;
  }
  *out << StringPrintf(
      "Drift (%s): each session against the others (leave one out): named when some parameter "
      "lies outside the others' new-session interval at 1 - %.3g/%d (Bonferroni over the %d "
      "parameters; t_%g multiplier %.3g), so a session like the others is named at most %.3g%% "
      "of the times\n",
      sensor, check.level, check.parameter_count, check.parameter_count, check.degrees_of_freedom,
      check.multiplier, 100.0 * check.level);
  for (const SessionDrift& drift : check.sessions) {
    const SessionDeviation& largest = drift.largest;
    *out << StringPrintf(
        "  session %d: largest %s, %.3g new-session sigma from the others' common value "
        "(p = %.2g on t_%g)",
        session_numbers[drift.session], names[largest.parameter].c_str(), largest.deviation,
        largest.p_value, check.degrees_of_freedom);
    if (!drift.drifting()) {
      *out << ": not named\n";
      continue;
    }
    *out << ": DRIFTS in";
    for (size_t i = 0; i < drift.outside.size(); ++i) {
      *out << StringPrintf("%s %s (%.3g sigma)", i == 0 ? "" : ",",
                           names[drift.outside[i].parameter].c_str(), drift.outside[i].deviation);
    }
    *out << "\n";
  }
  if (check.drifting.empty()) {
    *out << "  named: none\n";
    return;
  }
  *out << "  named:";
  for (int s : check.drifting) *out << " session " << session_numbers[s];
  *out << StringPrintf(" (%s)\n", sensor);
}

std::string GyroscopeSessionLine(const TriadSessionReport& session) {
  const GyroscopeSessionOutcome& g = session.gyroscope;
  const std::string file = session.gyroscope_path.empty() ? "" : session.gyroscope_path + ": ";
  if (!g.present) return "  gyroscope: " + file + "none in this log: not calibrated\n";
  if (!g.calibrated) {
    return StringPrintf("  gyroscope: %sread (%d samples); NOT calibrated: %s\n", file.c_str(),
                        g.samples, g.not_calibrated.c_str());
  }
  const GyroscopeMlResult& ml = g.calibration.ml;
  return StringPrintf(
      "  gyroscope: %s%d samples, %zu turns; fit chi2 %.1f on %d (p = %.2g); Verdict "
      "(gyroscope, %s)\n",
      file.c_str(), g.samples, ml.turns.size(), ml.chi2_gyroscope, ml.gyroscope_degrees_of_freedom,
      ml.gyroscope_p_value, VerdictCode(g.calibration.discovery.verdict_code));
}

void GyroscopeSection(const TriadSessionsReport& report, std::ostringstream* out) {
  const GyroscopeSessionsResult& g = report.gyroscope;
  *out << StringPrintf(
      "\nGyroscope (w = T K (u - b), docs/gyroscope.md; outputs in %s): each session's calibrated "
      "as calibrate_imu --mode=ml calibrates one log, then combined by the same random-effects "
      "model\n",
      GyroscopeOutputUnitName(report.gyroscope_options.session.unit));
  if (!g.combined) {
    *out << "  not combined: " << g.not_combined << " (each session's line above says why)\n";
    return;
  }
  const SessionRows rows = GyroscopeRows(report);
  *out << "  combined over sessions";
  for (int number : rows.session_numbers) *out << " " << number;
  if (rows.session_numbers.size() < report.sessions.size()) {
    *out << "; LEFT OUT:";
    for (size_t s = 0; s < report.sessions.size(); ++s) {
      if (!report.sessions[s].gyroscope.calibrated) *out << " session " << s + 1;
    }
    *out << " (not calibrated: each session's line above says why)";
  }
  *out << "\n";
  *out << "Per session: estimate (within-session sigma), each session calibrated on its own\n";
  PerSessionTable(rows, out);
  const RandomEffectsEstimate& first = g.random_effects[0];
  *out << StringPrintf(
      "Across sessions (%zu sessions; tau on %g degree(s) of freedom; a new session's 95%% "
      "interval is common +- t_%g(0.975) = %.3g x new_session)\n",
      g.sessions.size(), first.between.degrees_of_freedom, first.between.degrees_of_freedom,
      first.interval_multiplier);
  std::vector<std::string> suffixes;
  for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
    std::string suffix;
    // An offset in counts is also given in deg/s (times the common gain).
    if (i >= kGyroscopeOffsetX &&
        report.gyroscope_options.session.unit == GyroscopeOutputUnit::kCount) {
      const double gain = g.random_effects[kGyroscopeGainX + i - kGyroscopeOffsetX].common;
      suffix = StringPrintf(
          " (%.3g deg/s)", g.random_effects[i].new_session_stddev * std::fabs(gain) * 180.0 / M_PI);
    }
    suffixes.push_back(suffix);
  }
  AcrossSessionsTable(rows, {g.random_effects.begin(), g.random_effects.end()}, suffixes, out);
  DriftLines("gyroscope", g.drift, rows.names, rows.session_numbers, out);
}

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
    if (report.has_gyroscope) out << GyroscopeSessionLine(report.sessions[s]);
  }
  const SessionRows rows = TriadRows(report);
  out << "\nPer session: estimate (within-session sigma), each session calibrated on its own\n";
  PerSessionTable(rows, &out);
  const RandomEffectsEstimate& first = report.combined[0];
  out << StringPrintf(
      "\nAcross sessions (random effects per parameter; %d sessions, so tau rests on %g "
      "degree(s) of freedom: its interval is wide, and a new session's 95%% interval needs "
      "t_%g(0.975) = %.3g, not 1.96)\n",
      session_count, first.between.degrees_of_freedom, first.between.degrees_of_freedom,
      first.interval_multiplier);
  std::vector<std::string> suffixes;
  for (int p = 0; p < kTriadParameterCount; ++p) {
    suffixes.push_back(OffsetInMps2(p, report.combined[p].new_session_stddev,
                                    report.combined[kTriadGainX + p % 3].common));
  }
  AcrossSessionsTable(rows, {report.combined.begin(), report.combined.end()}, suffixes, &out);
  out << "  common: the device's value (weighted mean over sessions) and its sigma\n"
         "  stddev: WITHIN-session sigma, one session's own (mean over the sessions)\n"
         "  tau: BETWEEN-session sigma, how much the device moves from session to session;\n"
         "       p(tau=0): Cochran's test that the sessions agree within their own sigma\n"
         "  new_session: the sigma of a NEW session's estimate about `common`\n";
  out << StringPrintf(
      "  A new session's estimate lies, with 95%% probability, within common +- %.3g x "
      "new_session (Student t on %g dof).\n",
      first.interval_multiplier, first.between.degrees_of_freedom);
  DriftLines("accelerometer", report.drift, rows.names, rows.session_numbers, &out);
  if (report.has_gyroscope) GyroscopeSection(report, &out);
  return out.str();
}

namespace {

nlohmann::json DeviationJson(const SessionDeviation& deviation,
                             const std::vector<std::string>& names) {
  return {{"parameter", names[deviation.parameter]},
          {"value", deviation.value},
          {"others_common", deviation.others_common},
          {"others_stddev_new_session", deviation.others_new_session_stddev},
          {"deviation", deviation.deviation},
          {"p_value", deviation.p_value}};
}

nlohmann::json DriftJson(const SessionDriftCheck& check, const std::vector<std::string>& names,
                         const std::vector<int>& session_numbers) {
  nlohmann::json sessions = nlohmann::json::array(), drifting = nlohmann::json::array();
  for (const SessionDrift& drift : check.sessions) {
    nlohmann::json outside = nlohmann::json::array();
    for (const SessionDeviation& deviation : drift.outside)
      outside.push_back(DeviationJson(deviation, names));
    sessions.push_back({{"session", session_numbers[drift.session]},
                        {"drifting", drift.drifting()},
                        {"largest", DeviationJson(drift.largest, names)},
                        {"outside", outside}});
  }
  for (int s : check.drifting) drifting.push_back(session_numbers[s]);
  nlohmann::json json = {{"checked", check.checked}, {"rule", kDriftRule},
                         {"level", check.level},     {"parameter_count", check.parameter_count},
                         {"sessions", sessions},     {"drifting_sessions", drifting}};
  json["not_checked"] = check.checked ? nlohmann::json() : nlohmann::json(check.not_checked);
  json["parameter_level"] =
      check.checked ? nlohmann::json(check.parameter_level) : nlohmann::json();
  json["degrees_of_freedom"] =
      check.checked ? nlohmann::json(check.degrees_of_freedom) : nlohmann::json();
  json["multiplier"] = check.checked ? nlohmann::json(check.multiplier) : nlohmann::json();
  return json;
}

// The combined keys of one sensor, as the accelerometer's top level has them.
void CombinedJson(const SessionRows& rows, const std::vector<RandomEffectsEstimate>& combined,
                  nlohmann::json* json) {
  nlohmann::json parameters, common_stddev, stddev, new_session, between, interval, p_values,
      multiplier, units;
  for (size_t p = 0; p < rows.names.size(); ++p) {
    const std::string& name = rows.names[p];
    const RandomEffectsEstimate& e = combined[p];
    parameters[name] = e.common;
    common_stddev[name] = e.common_stddev;
    stddev[name] = e.within_stddev;
    new_session[name] = e.new_session_stddev;
    between[name] = e.between.stddev;
    interval[name] = {e.between.stddev_low, e.between.stddev_high};
    p_values[name] = e.between.homogeneity_p;
    multiplier[name] = e.interval_multiplier;
    units[name] = rows.units[p];
  }
  (*json)["parameters"] = parameters;
  (*json)["parameters_stddev"] = common_stddev;
  (*json)["stddev"] = stddev;
  (*json)["stddev_new_session"] = new_session;
  (*json)["between_session_stddev"] = between;
  (*json)["between_session_stddev_interval_95"] = interval;
  (*json)["between_session_p_value"] = p_values;
  (*json)["interval_multiplier_95"] = multiplier;
  (*json)["degrees_of_freedom"] = combined[0].between.degrees_of_freedom;
  (*json)["units"] = units;
}

nlohmann::json GyroscopeSessionJson(const TriadSessionReport& session, GyroscopeOutputUnit unit) {
  const GyroscopeSessionOutcome& g = session.gyroscope;
  nlohmann::json json = {
      {"present", g.present}, {"samples", g.samples}, {"calibrated", g.calibrated}};
  json["file"] =
      session.gyroscope_path.empty() ? nlohmann::json() : nlohmann::json(session.gyroscope_path);
  json["sha256"] =
      session.gyroscope_path.empty() ? nlohmann::json() : nlohmann::json(session.gyroscope_sha256);
  json["not_calibrated"] = g.calibrated ? nlohmann::json() : nlohmann::json(g.not_calibrated);
  if (!g.calibrated) return json;
  const GyroscopeMlResult& ml = g.calibration.ml;
  nlohmann::json parameters, stddev, units;
  for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
    const std::string name = GyroscopeCalibrationParameterName(i);
    parameters[name] = i < kGyroscopeOffsetX ? ml.parameters[i] : ml.offset[i - kGyroscopeOffsetX];
    stddev[name] = ml.stddev[i];
    units[name] = GyroscopeParameterUnit(i, unit);
  }
  json["parameters"] = parameters;
  json["stddev"] = stddev;
  json["units"] = units;
  json["turns"] = ml.turns.size();
  json["chi2"] = ml.chi2_gyroscope;
  json["dof"] = ml.gyroscope_degrees_of_freedom;
  json["p_value"] = ml.gyroscope_p_value;
  json["verdict"] = VerdictCode(g.calibration.discovery.verdict_code);
  json["verdict_text"] = g.calibration.discovery.verdict;
  return json;
}

nlohmann::json GyroscopeJson(const TriadSessionsReport& report) {
  const GyroscopeSessionsResult& g = report.gyroscope;
  nlohmann::json json;
  json["output_unit"] = GyroscopeOutputUnitName(report.gyroscope_options.session.unit);
  nlohmann::json combined = nlohmann::json::array(), left_out = nlohmann::json::array();
  for (int s : g.sessions) combined.push_back(s + 1);
  for (size_t s = 0; s < report.sessions.size(); ++s) {
    if (!report.sessions[s].gyroscope.calibrated)
      left_out.push_back(
          {{"session", s + 1}, {"why", report.sessions[s].gyroscope.not_calibrated}});
  }
  json["sessions_combined"] = combined;
  json["sessions_left_out"] = left_out;
  json["not_combined"] = g.combined ? nlohmann::json() : nlohmann::json(g.not_combined);
  if (!g.combined) {
    for (const char* key :
         {"parameters", "parameters_stddev", "stddev", "stddev_new_session",
          "between_session_stddev", "between_session_stddev_interval_95", "between_session_p_value",
          "interval_multiplier_95", "degrees_of_freedom", "units", "drift"})
      json[key] = nullptr;
    return json;
  }
  const SessionRows rows = GyroscopeRows(report);
  CombinedJson(rows, {g.random_effects.begin(), g.random_effects.end()}, &json);
  json["drift"] = DriftJson(g.drift, rows.names, rows.session_numbers);
  return json;
}

}  // namespace

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
    if (report.has_gyroscope)
      sessions.back()["gyroscope"] =
          GyroscopeSessionJson(session, report.gyroscope_options.session.unit);
  }
  json["sessions"] = sessions;
  const SessionRows rows = TriadRows(report);
  CombinedJson(rows, {report.combined.begin(), report.combined.end()}, &json);
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
       "Student t quantile t_{S-1}(0.975): tau^2 is estimated from S sessions"},
      {"drift", kDriftRule},
      {"gyroscope",
       "the gyroscope's 12 unknowns under the same keys, combined over the sessions whose "
       "gyroscope calibrated (null when no session's log has a gyroscope)"}};
  json["drift"] = DriftJson(report.drift, rows.names, rows.session_numbers);
  json["gyroscope"] = report.has_gyroscope ? GyroscopeJson(report) : nlohmann::json();
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

namespace {

double GyroscopeValue(const GyroscopeMlResult& ml, int i) {
  return i < kGyroscopeOffsetX ? ml.parameters[i] : ml.offset[i - kGyroscopeOffsetX];
}

void ByHeldOutSession(const LosoResult& loso, const std::vector<std::string>& session_names,
                      std::ostringstream* out) {
  *out << "  by held-out session (all kinds):";
  for (int scheme = 0; scheme < kSessionSchemeCount; ++scheme) {
    *out << StringPrintf("  %s", SessionSchemeName(static_cast<SessionScheme>(scheme)));
    for (size_t s = 0; s < session_names.size(); ++s) {
      const CoverageCount& c = loso.coverage_by_session[scheme][s];
      *out << StringPrintf(" %s %d/%d", session_names[s].c_str(), c.covered, c.total);
    }
  }
  *out << "\n";
}

// Every kind of a scheme together.
CoverageCount AllKinds(const CoverageTable& table, SessionScheme scheme) {
  CoverageCount all;
  for (const CoverageCount& count : table[static_cast<int>(scheme)]) {
    all.covered += count.covered;
    all.total += count.total;
  }
  return all;
}

void GyroscopeRepeatabilitySection(const TriadRepeatabilityReport& report,
                                   std::ostringstream* out) {
  const size_t device_count = report.device_names.size();
  const size_t session_count = report.session_names.size();
  *out << StringPrintf(
      "\nGyroscope (w = T K (u - b), outputs in %s): each log's calibrated as calibrate_imu "
      "--mode=ml calibrates it, its 12 unknowns combined per device as the accelerometer's\n",
      GyroscopeOutputUnitName(report.gyroscope_unit));
  for (size_t d = 0; d < device_count; ++d) {
    for (size_t s = 0; s < session_count; ++s) {
      const GyroscopeSessionOutcome& outcome = report.gyroscope_sessions[d][s];
      if (!outcome.calibrated) {
        *out << StringPrintf("  %s %s: NOT calibrated: %s\n", report.device_names[d].c_str(),
                             report.session_names[s].c_str(), outcome.not_calibrated.c_str());
      }
    }
  }
  for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
    *out << StringPrintf(
        "%s (%s): per session estimate (within-session sigma); device: tau [95%%], new-session "
        "sigma\n",
        GyroscopeCalibrationParameterName(i).c_str(),
        GyroscopeParameterUnit(i, report.gyroscope_unit).c_str());
    for (size_t d = 0; d < device_count; ++d) {
      *out << StringPrintf("  %-6s", report.device_names[d].c_str());
      for (size_t s = 0; s < session_count; ++s) {
        const GyroscopeSessionOutcome& outcome = report.gyroscope_sessions[d][s];
        const GyroscopeMlResult& ml = outcome.calibration.ml;
        *out << StringPrintf(
            " %24s", outcome.calibrated
                         ? StringPrintf("%.7g (%.2g)", GyroscopeValue(ml, i), ml.stddev[i]).c_str()
                         : "-");
      }
      const GyroscopeSessionsResult& device = report.gyroscope_per_device[d];
      if (!device.combined) {
        *out << "   not combined\n";
        continue;
      }
      const RandomEffectsEstimate& e = device.random_effects[i];
      *out << StringPrintf("   tau %.3g [%.2g, %.2g]  new %.3g\n", e.between.stddev,
                           e.between.stddev_low, e.between.stddev_high, e.new_session_stddev);
    }
  }
  if (!report.has_gyroscope_loso) {
    *out << "Leave one session out (gyroscope): not run: " << report.gyroscope_loso_not_run << "\n";
    return;
  }
  *out << StringPrintf(
      "Leave one session out (gyroscope): each of the %zu sessions predicted from the other %zu, "
      "the %zu devices whose every session's gyroscope calibrated, every unknown; covered when "
      "inside the 95%% interval (issue 44's target: >= 90%% in the device scheme)\n",
      session_count, session_count - 1, report.gyroscope_devices.size());
  CoverageRows(report.gyroscope_loso.coverage, out);
  for (int scheme = 0; scheme < kSessionSchemeCount; ++scheme) {
    const CoverageCount all =
        AllKinds(report.gyroscope_loso.coverage, static_cast<SessionScheme>(scheme));
    *out << StringPrintf("  %-8s all %s\n", SessionSchemeName(static_cast<SessionScheme>(scheme)),
                         CoverageCell(all).c_str());
  }
  ByHeldOutSession(report.gyroscope_loso, report.session_names, out);
}

nlohmann::json GyroscopeRepeatabilityJson(const TriadRepeatabilityReport& report) {
  nlohmann::json not_calibrated = nlohmann::json::array(), devices = nlohmann::json::array();
  for (size_t d = 0; d < report.device_names.size(); ++d) {
    for (size_t s = 0; s < report.session_names.size(); ++s) {
      const GyroscopeSessionOutcome& outcome = report.gyroscope_sessions[d][s];
      if (!outcome.calibrated) {
        not_calibrated.push_back({{"device", report.device_names[d]},
                                  {"session", report.session_names[s]},
                                  {"why", outcome.not_calibrated}});
      }
    }
    const GyroscopeSessionsResult& device = report.gyroscope_per_device[d];
    nlohmann::json json = {{"name", report.device_names[d]}, {"combined", device.combined}};
    if (device.combined) {
      nlohmann::json common, within, tau, new_session, units;
      for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
        const std::string name = GyroscopeCalibrationParameterName(i);
        const RandomEffectsEstimate& e = device.random_effects[i];
        common[name] = e.common;
        within[name] = e.within_stddev;
        tau[name] = e.between.stddev;
        new_session[name] = e.new_session_stddev;
        units[name] = GyroscopeParameterUnit(i, report.gyroscope_unit);
      }
      json["parameters"] = common;
      json["stddev"] = within;
      json["between_session_stddev"] = tau;
      json["stddev_new_session"] = new_session;
      json["interval_multiplier_95"] = device.random_effects[0].interval_multiplier;
      json["units"] = units;
    }
    devices.push_back(json);
  }
  nlohmann::json json = {{"output_unit", GyroscopeOutputUnitName(report.gyroscope_unit)},
                         {"not_calibrated", not_calibrated},
                         {"per_device", devices}};
  if (report.has_gyroscope_loso) {
    nlohmann::json names = nlohmann::json::array();
    for (int d : report.gyroscope_devices) names.push_back(report.device_names[d]);
    json["leave_one_session_out"] = {{"coverage", CoverageJson(report.gyroscope_loso.coverage)},
                                     {"devices", names},
                                     {"confidence", 0.95}};
  } else {
    json["leave_one_session_out"] = nullptr;
    json["leave_one_session_out_not_run"] = report.gyroscope_loso_not_run;
  }
  return json;
}

}  // namespace

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
  ByHeldOutSession(report.loso, report.session_names, &out);
  if (report.has_gyroscope) GyroscopeRepeatabilitySection(report, &out);
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
  if (report.has_gyroscope) json["gyroscope"] = GyroscopeRepeatabilityJson(report);
  if (report.has_monte_carlo) json["monte_carlo"] = RepeatabilityMonteCarloJson(report.monte_carlo);
  return json;
}

}  // namespace accelcal
