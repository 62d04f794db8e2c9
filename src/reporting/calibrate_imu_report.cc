#include "reporting/calibrate_imu_report.h"

#include <sstream>

#include "common/format.h"
#include "models/triad.h"

namespace accelcal {
namespace {

// What imu_tk printed on its Xsens example (issue 20), in block order, and the sensor's
// datasheet values (SOURCE.txt). Shown only beside a run on that very file.
constexpr const char* kImuTkPrinted[kTriadParameterCount] = {"0.0033593", "-0.0089064", "0.0213341",
                                                             "1/414.459", "1/412.01",   "1/414.649",
                                                             "33124.2",   "33275.2",    "32364.4"};
constexpr const char* kImuTkPrintedCosts[] = {"0.134724", "0.131345", "0.126126",
                                              "0.120558", "0.120131", "0.120586",
                                              "0.121338", "0.121422", "0.13824"};
constexpr int kImuTkPrintedIntervals[] = {42, 40, 39, 38, 38, 38, 38, 38, 38};
constexpr const char* kDatasheet[kTriadParameterCount] = {
    "(0.01)", "(0.01)", "(0.01)", "1/415", "1/413", "1/415", "33123", "33276", "32360"};

bool IsImuTkExample(const CalibrateImuReport& report) {
  return report.log_sha256 == kImuTkXsensAccSha256 && report.options.min_multiplier == 2 &&
         report.options.max_multiplier == 10;
}

std::string Axis(int k) { return std::string(1, "xyz"[k]); }

}  // namespace

std::string CalibrateImuTable(const CalibrateImuReport& report, bool full_solver_report) {
  const ImuTkResult& result = report.result;
  const ImuTkOptions& options = report.options;
  const bool example = IsImuTkExample(report);
  std::ostringstream out;
  out << StringPrintf(
      "calibrate_imu, mode imu_tk: imu_tk's accelerometer calibration (Tedaldi et al., ICRA "
      "2014), g = %.10g m/s^2\n",
      options.gravity_mps2);
  out << StringPrintf("log: %zu samples, t = %.10g .. %.10g s, %s\n", report.sample_count,
                      report.first_t_s, report.last_t_s, report.log_layout.c_str());
  out << StringPrintf(
      "initial rest: samples 0..%d (to t = %.10g s, --init_rest_s=%g), variance norm %.6g "
      "(unit^2)\n\n",
      result.rest_end, report.rest_end_s, options.init_rest_s, result.rest_variance_norm);
  out << StringPrintf(
      "Threshold sweep: static where the variance norm over %d samples < k x %.6g; the first "
      "%d samples of each interval of at least %d; at least %d intervals\n",
      options.window_samples, result.rest_variance_norm, options.interval_samples,
      options.interval_samples, options.min_intervals);
  out << "   k  threshold  detected  used  final cost (m/s^2)^2  iterations"
      << (example ? "   imu_tk printed (cost, intervals)" : "") << "\n";
  for (size_t i = 0; i < result.sweep.size(); ++i) {
    const ImuTkSweepEntry& entry = result.sweep[i];
    std::string cost = entry.solved ? StringPrintf("%-20.6g", entry.cost)
                                    : StringPrintf("%-20s", "(too few intervals)");
    out << StringPrintf("  %2d  %9.6g  %8d  %4d  %s  %10d", entry.multiplier, entry.threshold,
                        entry.detected_intervals, entry.used_intervals, cost.c_str(),
                        entry.iterations);
    if (example) {
      const int j = entry.multiplier - 2;
      out << StringPrintf("   %-10s %d", kImuTkPrintedCosts[j], kImuTkPrintedIntervals[j]);
    }
    out << (static_cast<int>(i) == result.chosen ? "   <- chosen" : "") << "\n";
  }
  const ImuTkSweepEntry& best = result.best();
  out << StringPrintf(
      "\nChosen: k = %d, the lowest final cost %.6g (m/s^2)^2 over %d intervals (%d samples)\n\n",
      best.multiplier, best.cost, best.used_intervals,
      best.used_intervals * options.interval_samples);

  out << "Parameters (a = T K (u - b), docs/triad.md)\n";
  out << StringPrintf("  %-16s %-14s %-16s", "parameter", "unit", "estimate");
  if (example) out << StringPrintf(" %-16s %s", "imu_tk printed", "datasheet");
  out << "\n";
  const auto& infos = TriadParameterInfos();
  for (int p = 0; p < kTriadParameterCount; ++p) {
    std::string value = StringPrintf("%.8g", best.parameters[p]);
    if (p >= kTriadScaleX && p <= kTriadScaleZ) {
      value = StringPrintf("1/%.6g", 1.0 / best.parameters[p]);
    }
    out << StringPrintf("  %-16s %-14s %-16s", infos[p].name, infos[p].unit, value.c_str());
    if (example) out << StringPrintf(" %-16s %s", kImuTkPrinted[p], kDatasheet[p]);
    out << "\n";
  }
  out << "  (scale_k is printed as 1/(counts per m/s^2), the inverse scale imu_tk prints; the "
         "datasheet gives the misalignment only to 0.01)\n\n";

  out << StringPrintf(
      "Static intervals at k = %d (samples 0-based, inclusive; noise = sample "
      "standard deviation)\n",
      best.multiplier);
  out << "    #  start    end   start_s    end_s  dur_s      mean x      mean y      mean z  "
         "noise x  noise y  noise z  used\n";
  for (size_t i = 0; i < result.intervals.size(); ++i) {
    const StaticInterval& s = result.intervals[i];
    out << StringPrintf(
        "  %3zu %6d %6d %9.3f %8.3f %6.2f %11.2f %11.2f %11.2f %8.3f %8.3f %8.3f  %s\n", i + 1,
        s.start, s.end, s.start_s, s.end_s, s.duration_s, s.mean[0], s.mean[1], s.mean[2],
        s.noise_stddev[0], s.noise_stddev[1], s.noise_stddev[2],
        result.interval_used[i] ? "yes" : "no (short)");
  }
  out << "\n" << result.brief_report << "\n";
  if (full_solver_report) {
    for (const ImuTkSweepEntry& entry : result.sweep) {
      if (entry.solved)
        out << StringPrintf("  k = %d: %s\n", entry.multiplier, entry.termination.c_str());
    }
  }
  return out.str();
}

nlohmann::json CalibrateImuJson(const CalibrateImuReport& report) {
  const ImuTkResult& result = report.result;
  const ImuTkOptions& options = report.options;
  const ImuTkSweepEntry& best = result.best();
  nlohmann::json json;
  json["mode"] = "imu_tk";
  json["model"] = "a = T K (u - b), docs/triad.md";
  json["gravity_mps2"] = options.gravity_mps2;
  json["log"] = {{"path", report.log_path},
                 {"layout", report.log_layout},
                 {"samples", report.sample_count},
                 {"first_t_s", report.first_t_s},
                 {"last_t_s", report.last_t_s}};
  json["initial_rest"] = {{"duration_s", options.init_rest_s},
                          {"end_sample", result.rest_end},
                          {"end_t_s", report.rest_end_s},
                          {"variance", result.rest_variance},
                          {"variance_norm", result.rest_variance_norm}};
  json["detector"] = {{"window_samples", options.window_samples},
                      {"interval_samples", options.interval_samples},
                      {"min_intervals", options.min_intervals}};
  nlohmann::json sweep = nlohmann::json::array();
  for (const ImuTkSweepEntry& entry : result.sweep) {
    nlohmann::json item = {{"k", entry.multiplier},
                           {"threshold", entry.threshold},
                           {"detected_intervals", entry.detected_intervals},
                           {"intervals", entry.used_intervals},
                           {"solved", entry.solved}};
    item["cost"] = entry.solved ? nlohmann::json(entry.cost) : nlohmann::json(nullptr);
    if (entry.solved) {
      item["iterations"] = entry.iterations;
      item["termination"] = entry.termination;
    }
    sweep.push_back(item);
  }
  json["threshold_sweep"] = sweep;
  json["chosen_k"] = best.multiplier;
  json["cost"] = best.cost;
  json["cost_definition"] = "1/2 sum_i (g - |a_i|)^2, (m/s^2)^2, Ceres' final cost";
  nlohmann::json parameters;
  nlohmann::json units;
  const auto& infos = TriadParameterInfos();
  for (int p = 0; p < kTriadParameterCount; ++p) {
    parameters[infos[p].name] = best.parameters[p];
    units[infos[p].name] = infos[p].unit;
  }
  json["parameters"] = parameters;
  json["units"] = units;
  nlohmann::json inverse;
  for (int k = 0; k < 3; ++k)
    inverse["inverse_scale_" + Axis(k)] = 1.0 / best.parameters[kTriadScaleX + k];
  inverse["unit"] = "count/(m/s^2)";
  json["inverse_scale"] = inverse;
  nlohmann::json intervals = nlohmann::json::array();
  for (size_t i = 0; i < result.intervals.size(); ++i) {
    const StaticInterval& s = result.intervals[i];
    intervals.push_back({{"start", s.start},
                         {"end", s.end},
                         {"start_s", s.start_s},
                         {"end_s", s.end_s},
                         {"duration_s", s.duration_s},
                         {"mean", s.mean},
                         {"noise", s.noise_stddev},
                         {"used", static_cast<bool>(result.interval_used[i])}});
  }
  json["intervals"] = intervals;
  json["intervals_note"] =
      "at the chosen k; start and end are 0-based sample indices, inclusive; mean and noise "
      "(sample standard deviation) per axis in the log's unit";
  if (IsImuTkExample(report)) {
    nlohmann::json printed;
    for (int p = 0; p < kTriadParameterCount; ++p) printed[infos[p].name] = kImuTkPrinted[p];
    nlohmann::json datasheet;
    for (int p = 0; p < kTriadParameterCount; ++p) datasheet[infos[p].name] = kDatasheet[p];
    json["references"] = {{"imu_tk_printed", printed},
                          {"imu_tk_printed_costs", kImuTkPrintedCosts},
                          {"imu_tk_printed_intervals", kImuTkPrintedIntervals},
                          {"datasheet", datasheet}};
  }
  json["solver"] = result.brief_report;
  return json;
}

}  // namespace accelcal
