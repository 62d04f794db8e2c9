#include "reporting/calibrate_imu_report.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <utility>
#include <vector>

#include "common/format.h"
#include "estimation/statistics/chi_square.h"
#include "io/imu_tk_calib_file.h"
#include "models/triad.h"
#include "reporting/gyroscope_report.h"
#include "reporting/triad_discovery_report.h"

namespace accelcal {

// What imu_tk printed on its Xsens example (issue 20), in block order, and the sensor's
// datasheet values (SOURCE.txt). Shown only beside a run on that very file.
const char* const kImuTkPrinted[kTriadParameterCount] = {"0.0033593", "-0.0089064", "0.0213341",
                                                         "1/414.459", "1/412.01",   "1/414.649",
                                                         "33124.2",   "33275.2",    "32364.4"};
namespace {

constexpr const char* kImuTkPrintedCosts[] = {"0.134724", "0.131345", "0.126126",
                                              "0.120558", "0.120131", "0.120586",
                                              "0.121338", "0.121422", "0.13824"};
constexpr int kImuTkPrintedIntervals[] = {42, 40, 39, 38, 38, 38, 38, 38, 38};

}  // namespace

const char* const kDatasheet[kTriadParameterCount] = {
    "(0.01)", "(0.01)", "(0.01)", "1/415", "1/413", "1/415", "33123", "33276", "32360"};

namespace {

// What imu_tk printed for the gyroscope on its Xsens pair (issue 32), each parameter as it
// follows from its printed matrices (yz = -T(0,1), ...), and the datasheet's (SOURCE.txt; it
// gives no gyroscope misalignment). In block order, then the three offsets.
constexpr const char* kImuTkPrintedGyroscope[kGyroscopeParameterCount + 3] = {
    "-0.00593634", "0.00111101", "0.0535569", "0.00808812", "-0.0253067", "-0.0025513",
    "1/4777.96",   "1/4764.21",  "1/4773.66", "32777.1",    "32459.8",    "32511.8"};
constexpr const char* kDatasheetGyroscope[kGyroscopeParameterCount + 3] = {
    "-", "-", "-", "-", "-", "-", "1/4778", "1/4758", "1/4766", "32768", "32466", "32485"};
constexpr char kImuTkPrintedResidual[] = "0.00150696";
}  // namespace
const char* DatasheetGyroscopeValue(int i) { return kDatasheetGyroscope[i]; }
namespace {
// imu_tk's printout on that pair, as its calibrateAccGyro writes it (cout << "Gyroscopes
// calibration: residual " << cost << endl << gyro_calib_ << endl << ...: the CalibratedTriad's
// operator<< ends its bias vector with endl, and the endl after it leaves an empty line).
constexpr char kImuTkPrintedGyroscopeText[] =
    "Gyroscopes calibration: residual 0.00150696\n"
    "Misalignment Matrix\n"
    "         1 0.00593634 0.00111101\n"
    "0.00808812          1 -0.0535569\n"
    " 0.0253067 -0.0025513          1\n"
    "Scale Matrix\n"
    "0.000209295           0           0\n"
    "          0 0.000209899           0\n"
    "          0           0 0.000209483\n"
    "Bias Vector\n"
    "32777.1\n"
    "32459.8\n"
    "32511.8\n"
    "\n"
    "Gyroscopes calibration: inverse scale factors:\n"
    "4777.96\n"
    "4764.21\n"
    "4773.66\n";

}  // namespace

bool TriadDiscoveryKeptEffects(const TriadDiscoveryResult& discovery) {
  return !discovery.effects.empty() && discovery.explained_by_shape.empty() &&
         !discovery.final_fit.effects_estimated.empty();
}

std::vector<int> TriadTermsInOrder(const TriadMlResult& ml) {
  std::vector<int> terms = ml.effects_estimated;
  std::sort(terms.begin(), terms.end());
  return terms;
}

Eigen::MatrixXd TriadMlCovariance(const TriadMlResult& ml) {
  const std::vector<int> terms = TriadTermsInOrder(ml);
  const int n = kTriadParameterCount + static_cast<int>(terms.size());
  Eigen::MatrixXd covariance(n, n);
  for (int i = 0; i < kTriadParameterCount; ++i)
    for (int j = 0; j < kTriadParameterCount; ++j) covariance(i, j) = ml.covariance[i][j];
  for (size_t a = 0; a < terms.size(); ++a) {
    const int row = kTriadParameterCount + static_cast<int>(a);
    for (int i = 0; i < kTriadParameterCount; ++i) {
      covariance(row, i) = covariance(i, row) = ml.cross_covariance[i][terms[a]];
    }
    for (size_t b = 0; b < terms.size(); ++b) {
      covariance(row, kTriadParameterCount + static_cast<int>(b)) =
          ml.effects_covariance[terms[a]][terms[b]];
    }
  }
  return covariance;
}

void TakeSessionCalibration(TriadSessionCalibration session, CalibrateImuReport* report) {
  report->noise_floor = std::move(session.detection);
  report->pose_intervals = std::move(session.pose_intervals);
  report->ml_sample_count = session.sample_count;
  report->pose_noise = std::move(session.pose_noise);
  report->allan_noise = session.allan_noise;
  report->ml_options = std::move(session.ml_options);
  report->ml = std::move(session.ml);
  report->discovery_options = std::move(session.discovery_options);
  report->discovery = std::move(session.discovery);
  // The calibration is the model discovery settled on (issue 44, item 7).
  if (TriadDiscoveryKeptEffects(report->discovery)) report->ml = report->discovery.final_fit;
  report->has_ml_baseline = !report->ml.effects_estimated.empty();
  if (report->has_ml_baseline) report->ml_baseline = report->discovery.baseline;
  // On the sigmas the fit description vouches for: scaled by the understatement it states when
  // the pose means scatter beyond the noise model (issue 45: "Poorly determined: none" on sigmas
  // it had just called understated by 19x).
  const double understated = SigmaUnderstatement(report->ml, report->discovery);
  TriadMlResult scaled = report->ml;
  for (int p = 0; p < kTriadParameterCount; ++p) {
    scaled.stddev[p] *= understated;
    for (int q = 0; q < kTriadParameterCount; ++q)
      scaled.covariance[p][q] *= understated * understated;
  }
  report->poorly_determined =
      PoorlyDeterminedTriadParameters(scaled, TriadOutputUnitName(report->unit));
  if (understated > 1.0) {
    for (TriadPoorlyDetermined& entry : report->poorly_determined) {
      entry.reason += StringPrintf(
          " (its sigma scaled by sqrt(chi2/dof) = %.2g: the pose means scatter more than the "
          "noise model allows)",
          understated);
    }
  }
}

nlohmann::json PoorlyDeterminedJson(const std::vector<TriadPoorlyDetermined>& list) {
  nlohmann::json json = nlohmann::json::array();
  for (const TriadPoorlyDetermined& entry : list) {
    nlohmann::json correlated = nlohmann::json::array();
    for (const TriadCorrelatedParameter& other : entry.correlated_with)
      correlated.push_back({{"parameter", other.parameter}, {"correlation", other.correlation}});
    json.push_back({{"parameter", entry.parameter},
                    {"reason", entry.reason},
                    {"sigma", entry.sigma},
                    {"threshold", entry.threshold},
                    {"sigma_over_threshold", entry.sigma_over_threshold},
                    {"correlated_with", correlated},
                    {"suggestion", entry.suggestion}});
  }
  return json;
}

std::string PoorlyDeterminedLines(const std::string& label, const std::string& subject,
                                  const std::vector<PoorlyDeterminedParameter>& list,
                                  const std::function<double(int)>& value) {
  const DeterminationThresholds thresholds;
  if (list.empty()) {
    return StringPrintf(
        "%s: none (every sigma within its threshold: angles %g rad, gains %g of "
        "the gain, offsets %g x the axis's per-sample noise; no |correlation| > %g)\n",
        label.c_str(), thresholds.angle_sigma_rad, thresholds.gain_relative_sigma,
        thresholds.offset_noise_fraction, thresholds.correlation);
  }
  std::string text = StringPrintf(
      "%s (estimated and written, but %s do not vouch for them; "
      "--calibration_out names them too): %s\n",
      label.c_str(), subject.c_str(), PoorlyDeterminedNames(list).c_str());
  for (const PoorlyDeterminedParameter& entry : list) {
    text += StringPrintf("  %s = %.6g +- %.3g: %s\n    would be determined by %s\n",
                         entry.parameter.c_str(), value(entry.index), entry.sigma,
                         entry.reason.c_str(), entry.suggestion.c_str());
  }
  return text;
}

std::string PoorlyDeterminedTable(const CalibrateImuReport& report) {
  return PoorlyDeterminedLines("Poorly determined", "these poses", report.poorly_determined,
                               [&](int p) { return report.ml.parameters[p]; });
}

bool IsImuTkExample(const CalibrateImuReport& report) {
  return report.log_sha256 == kImuTkXsensAccSha256 && report.options.min_multiplier == 2 &&
         report.options.max_multiplier == 10;
}

bool IsImuTkGyroscopeExample(const CalibrateImuReport& report) {
  return report.has_gyroscope_calibration && IsImuTkExample(report) &&
         report.gyroscope_sha256 == kImuTkXsensGyroSha256;
}

std::string ImuTkGyroscopePrintout(const ImuTkGyroscopeResult& result) {
  // imu_tk's calibrateAccGyro: cout << "Gyroscopes calibration: residual " << final_cost << endl
  // << gyro_calib_ << endl << "Gyroscopes calibration: inverse scale factors:" << endl << 1/s_x
  // << endl ..., on a stream of default precision; the triad prints as its .calib file's
  // matrices, each under its name.
  const std::array<std::string, 3> matrices =
      ImuTkTriadMatrices(ImuTkGyroscopeTriad(result.parameters, result.offset));
  std::ostringstream out;
  out << "Gyroscopes calibration: residual " << result.cost << "\n"
      << "Misalignment Matrix\n"
      << matrices[0] << "\nScale Matrix\n"
      << matrices[1] << "\nBias Vector\n"
      << matrices[2] << "\n\n"
      << "Gyroscopes calibration: inverse scale factors:\n";
  for (const double inverse : result.inverse_gains()) out << inverse << "\n";
  return out.str();
}

namespace {

std::string Axis(int k) { return std::string(1, "xyz"[k]); }

constexpr double kDegreesPerRadian = 180.0 / M_PI;

// The turns' residual angles (rad): median, root mean square, largest and its turn (0-based).
struct ResidualAngleSummary {
  double median = 0.0;
  double rms = 0.0;
  double largest = 0.0;
  int largest_turn = 0;
};

ResidualAngleSummary SummariseResidualAngles(const std::vector<ImuTkGyroscopeTurn>& turns) {
  ResidualAngleSummary summary;
  std::vector<double> angles;
  for (size_t p = 0; p < turns.size(); ++p) {
    const double angle = turns[p].residual_angle_rad;
    angles.push_back(angle);
    summary.rms += angle * angle;
    if (angle > summary.largest) {
      summary.largest = angle;
      summary.largest_turn = static_cast<int>(p);
    }
  }
  if (angles.empty()) return summary;
  summary.rms = std::sqrt(summary.rms / angles.size());
  std::sort(angles.begin(), angles.end());
  const size_t n = angles.size();
  summary.median = n % 2 == 1 ? angles[n / 2] : 0.5 * (angles[n / 2 - 1] + angles[n / 2]);
  return summary;
}

// The gyroscope's part of the imu_tk table, after the accelerometer's.
std::string GyroscopeTable(const CalibrateImuReport& report, bool full_solver_report) {
  const ImuTkGyroscopeResult& g = report.gyroscope;
  const ImuTkGyroscopeOptions& options = report.gyroscope_options;
  const GyroscopeOutputUnit unit = report.gyroscope_unit;
  const char* unit_name = GyroscopeOutputUnitName(unit);
  const bool example = IsImuTkGyroscopeExample(report);
  std::ostringstream out;
  out << "\nGyroscope: imu_tk's gyroscope calibration (Tedaldi et al., ICRA 2014, IV-C), "
         "w = T K (u - b) in rad/s (docs/gyroscope.md)\n";
  out << StringPrintf(
      "gyroscope log: %s, %zu samples, outputs in %s (--gyro_unit)\n",
      report.gyroscope_path.empty() ? "the log's gyroscope columns" : report.gyroscope_path.c_str(),
      report.gyroscope_samples, unit_name);
  out << StringPrintf(
      "offset b: the mean of the initial rest, samples 0..%d (--gyro_bias=rest, imu_tk's: not "
      "estimated)\n",
      g.rest_end);
  out << StringPrintf("start: angles 0, gains %.9g (rad/s) per %s (%s)\n",
                      options.initial[kGyroscopeGainX], unit_name,
                      report.initial_gyro_gain_from.c_str());
  out << StringPrintf(
      "turns: %zu, one between each two consecutive of the %zu intervals used at k = %d, the "
      "rate integrated from the last sample of one to the sample before the next (%s)\n",
      g.turns.size(), g.turns.size() + 1, report.result.best().multiplier,
      options.data_period_s > 0.0 ? StringPrintf("steps of %g s", options.data_period_s).c_str()
                                  : "steps from the time stamps");
  out << StringPrintf(
      "residual: %.6g (Ceres' final cost 1/2 sum |r|^2 over the turns, r = R^T g_before - "
      "g_after of unit vectors; %.6g at the start)",
      g.cost, g.initial_cost);
  if (example) out << "   imu_tk printed " << kImuTkPrintedResidual;
  out << "\n\n";

  out << "Parameters (w = T K (u - b), docs/gyroscope.md)\n";
  out << StringPrintf(example ? "  %-26s %-16s %-16s" : "  %-26s %-16s %s", "parameter", "unit",
                      "estimate");
  if (example) out << StringPrintf(" %-16s %s", "imu_tk printed", "datasheet");
  out << "\n";
  const auto& infos = GyroscopeParameterInfos();
  for (int p = 0; p < kGyroscopeParameterCount + 3; ++p) {
    const bool offset = p >= kGyroscopeParameterCount;
    const double value = offset ? g.offset[p - kGyroscopeParameterCount] : g.parameters[p];
    std::string text = StringPrintf("%.8g", value);
    if (!offset && p >= kGyroscopeGainX && unit == GyroscopeOutputUnit::kCount)
      text = StringPrintf("1/%.6g", 1.0 / value);
    const std::string name = offset ? "gyroscope_offset_" + Axis(p - kGyroscopeParameterCount)
                                    : std::string(infos[p].name);
    out << StringPrintf(example ? "  %-26s %-16s %-16s" : "  %-26s %-16s %s", name.c_str(),
                        offset ? unit_name : GyroscopeParameterUnit(p, unit).c_str(), text.c_str());
    if (example)
      out << StringPrintf(" %-16s %s", kImuTkPrintedGyroscope[p], kDatasheetGyroscope[p]);
    out << "\n";
  }
  out << "  (";
  if (unit == GyroscopeOutputUnit::kCount)
    out << "gyroscope_gain_k is printed as 1/(counts per rad/s), the inverse scale imu_tk prints; ";
  out << "the offsets are the rest's means, not estimated";
  if (example) out << "; the datasheet gives no gyroscope misalignment";
  out << ")\n\n";

  const std::string printout = ImuTkGyroscopePrintout(g);
  out << "imu_tk's printout of this calibration (--imu_tk_calib_out writes its three matrices as "
         "PREFIX_gyro.calib):\n";
  std::istringstream lines(printout);
  for (std::string line; std::getline(lines, line);)
    out << (line.empty() ? "" : "  ") << line << "\n";
  if (example) {
    out << (printout == kImuTkPrintedGyroscopeText
                ? "  (imu_tk printed exactly these lines on this log)\n"
                : "  imu_tk printed on this log, differently:\n" +
                      std::string(kImuTkPrintedGyroscopeText));
  }
  out << "\n";

  out << "Turns (intervals numbered as in the table above; angles in deg; residual: the angle by "
         "which the calibrated rates miss the turn between the two gravity directions)\n";
  out << "     #  intervals    samples integrated    dur_s  turn_deg  residual_deg\n";
  for (size_t p = 0; p < g.turns.size(); ++p) {
    const ImuTkGyroscopeTurn& turn = g.turns[p];
    out << StringPrintf(
        "  %4zu  %3d -> %3d  %8d .. %-8d  %6.2f  %8.2f  %12.4f\n", p + 1, turn.interval_before + 1,
        turn.interval_after + 1, turn.first_sample, turn.last_sample,
        report.result.intervals[turn.interval_after].start_s -
            report.result.intervals[turn.interval_before].end_s,
        turn.turn_angle_rad * kDegreesPerRadian, turn.residual_angle_rad * kDegreesPerRadian);
  }
  const ResidualAngleSummary summary = SummariseResidualAngles(g.turns);
  out << StringPrintf(
      "  residual angle over the %zu turns: median %.4g deg, rms %.4g deg, largest %.4g deg "
      "(turn %d)\n\n",
      g.turns.size(), summary.median * kDegreesPerRadian, summary.rms * kDegreesPerRadian,
      summary.largest * kDegreesPerRadian, summary.largest_turn + 1);
  out << (full_solver_report ? g.summary.FullReport() : g.summary.BriefReport()) << "\n";
  return out.str();
}

// The gyroscope's object of the imu_tk JSON.
nlohmann::json GyroscopeJson(const CalibrateImuReport& report) {
  const ImuTkGyroscopeResult& g = report.gyroscope;
  const GyroscopeOutputUnit unit = report.gyroscope_unit;
  const char* unit_name = GyroscopeOutputUnitName(unit);
  const auto& infos = GyroscopeParameterInfos();
  nlohmann::json parameters, units, initial;
  for (int p = 0; p < kGyroscopeParameterCount; ++p) {
    parameters[infos[p].name] = g.parameters[p];
    units[infos[p].name] = GyroscopeParameterUnit(p, unit);
    initial[infos[p].name] = report.gyroscope_options.initial[p];
  }
  const ImuTkCalibratedTriad triad = ImuTkGyroscopeTriad(g.parameters, g.offset);
  nlohmann::json misalignment = nlohmann::json::array();
  nlohmann::json scale = nlohmann::json::array();
  for (int row = 0; row < 3; ++row) {
    misalignment.push_back({triad.misalignment[3 * row], triad.misalignment[3 * row + 1],
                            triad.misalignment[3 * row + 2]});
    nlohmann::json scale_row = {0.0, 0.0, 0.0};
    scale_row[row] = triad.scale[row];
    scale.push_back(scale_row);
  }
  const std::array<double, 3> inverse_gains = g.inverse_gains();
  nlohmann::json inverse = {{"x", inverse_gains[0]},
                            {"y", inverse_gains[1]},
                            {"z", inverse_gains[2]},
                            {"unit", std::string(unit_name) + "/(rad/s)"}};
  nlohmann::json turns = nlohmann::json::array();
  for (const ImuTkGyroscopeTurn& turn : g.turns) {
    turns.push_back({{"interval_before", turn.interval_before},
                     {"interval_after", turn.interval_after},
                     {"first_sample", turn.first_sample},
                     {"last_sample", turn.last_sample},
                     {"gravity_before", turn.gravity_before},
                     {"gravity_after", turn.gravity_after},
                     {"turn_angle_rad", turn.turn_angle_rad},
                     {"residual_angle_rad", turn.residual_angle_rad},
                     {"residual", turn.residual}});
  }
  const ResidualAngleSummary summary = SummariseResidualAngles(g.turns);
  nlohmann::json json = {
      {"model", "w = T K (u - b), docs/gyroscope.md"},
      {"path", report.gyroscope_path.empty() ? nlohmann::json(nullptr)
                                             : nlohmann::json(report.gyroscope_path)},
      {"samples", report.gyroscope_samples},
      {"unit", unit_name},
      {"offset_from", "rest"},
      {"rest_end_sample", g.rest_end},
      {"initial_guess",
       {{"parameters", initial}, {"units", units}, {"gain_from", report.initial_gyro_gain_from}}},
      {"data_period_s", report.gyroscope_options.data_period_s > 0.0
                            ? nlohmann::json(report.gyroscope_options.data_period_s)
                            : nlohmann::json(nullptr)},
      {"parameters", parameters},
      {"units", units},
      {"offset", g.offset},
      {"offset_unit", unit_name},
      {"misalignment_matrix", misalignment},
      {"scale_matrix", scale},
      {"bias_vector", triad.bias},
      {"inverse_gain", inverse},
      {"cost", g.cost},
      {"initial_cost", g.initial_cost},
      {"cost_definition",
       "1/2 sum over the turns of |R^T g_before - g_after|^2 (unit vectors), Ceres' final cost: "
       "imu_tk's printed 'Gyroscopes calibration: residual'"},
      {"turns", turns},
      {"residual_angle_summary",
       {{"median_rad", summary.median},
        {"rms_rad", summary.rms},
        {"largest_rad", summary.largest},
        {"largest_turn", summary.largest_turn}}},
      {"imu_tk_printout", ImuTkGyroscopePrintout(g)},
      {"solver", g.summary.BriefReport()}};
  if (IsImuTkGyroscopeExample(report)) {
    nlohmann::json printed, datasheet;
    for (int p = 0; p < kGyroscopeParameterCount + 3; ++p) {
      const std::string name = p < kGyroscopeParameterCount
                                   ? std::string(infos[p].name)
                                   : "gyroscope_offset_" + Axis(p - kGyroscopeParameterCount);
      printed[name] = kImuTkPrintedGyroscope[p];
      datasheet[name] = kDatasheetGyroscope[p];
    }
    json["references"] = {{"imu_tk_printed", printed},
                          {"imu_tk_printed_residual", kImuTkPrintedResidual},
                          {"imu_tk_printout", kImuTkPrintedGyroscopeText},
                          {"datasheet", datasheet}};
  } else {
    json["references"] = nullptr;
  }
  return json;
}

std::string LogLine(const CalibrateImuReport& report) {
  std::string text =
      StringPrintf("log: %zu samples, t = %.10g .. %.10g s, %s, outputs in %s (--unit)\n",
                   report.sample_count, report.first_t_s, report.last_t_s,
                   report.log_layout.c_str(), TriadOutputUnitName(report.unit));
  for (const std::string& note : report.log_notes) text += "  read: " + note + "\n";
  return text;
}

// An interval as both modes write it; each mode adds its own fields.
nlohmann::json IntervalJson(const StaticInterval& s) {
  return {
      {"start", s.start},           {"end", s.end},   {"start_s", s.start_s},   {"end_s", s.end_s},
      {"duration_s", s.duration_s}, {"mean", s.mean}, {"noise", s.noise_stddev}};
}

// How the samples' times were found (docs/json.md, log.time).
nlohmann::json TimingJson(const ImuLogTiming& timing) {
  auto or_null = [](bool known, double value) {
    return known ? nlohmann::json(value) : nlohmann::json(nullptr);
  };
  nlohmann::json bursts = nullptr;
  if (timing.bursts.bursty) {
    bursts = {{"steps", timing.bursts.steps},
              {"share_below_third_period", timing.bursts.short_share},
              {"share_above_1_5_periods", timing.bursts.long_share},
              {"period_s", timing.bursts.period_s},
              {"median_step_s", timing.bursts.median_step_s},
              {"mean_step_s", timing.bursts.mean_step_s},
              {"mean_rate_hz", timing.bursts.mean_rate_hz()}};
  }
  const IndexClockFit& fit = timing.fit;
  return {{"from", timing.from},
          {"index_column", timing.index_column.empty() ? nlohmann::json(nullptr)
                                                       : nlohmann::json(timing.index_column)},
          {"host_time_bursts", bursts},
          {"fitted_rate_hz", or_null(timing.rate_fitted, fit.rate_hz)},
          {"fitted_rate_tolerance_hz", or_null(timing.rate_fitted, fit.rate_tolerance_hz)},
          {"nominal_rate_hz",
           or_null(timing.rate_fitted && fit.nominal_rate_hz > 0.0, fit.nominal_rate_hz)},
          {"clock_drift_ppm",
           or_null(timing.rate_fitted && fit.nominal_rate_hz > 0.0, fit.clock_drift_ppm)},
          {"largest_host_delay_s", or_null(timing.rate_fitted, fit.largest_delay_s)},
          {"dropped_samples", timing.dropped_samples < 0 ? nlohmann::json(nullptr)
                                                         : nlohmann::json(timing.dropped_samples)}};
}

nlohmann::json LogJson(const CalibrateImuReport& report) {
  return {{"path", report.log_path},
          {"layout", report.log_layout},
          {"unit", TriadOutputUnitName(report.unit)},
          {"samples", report.sample_count},
          {"first_t_s", report.first_t_s},
          {"last_t_s", report.last_t_s},
          {"read_notes", report.log_notes},
          {"time", TimingJson(report.log_timing)},
          {"metadata", report.log_metadata},
          {"gyroscope_samples", report.gyroscope_samples}};
}

}  // namespace

std::string CalibrateImuMlTable(const CalibrateImuReport& report, bool full_solver_report);
nlohmann::json CalibrateImuMlJson(const CalibrateImuReport& report);

std::string CalibrateImuTable(const CalibrateImuReport& report, bool full_solver_report) {
  if (report.mode == "ml") return CalibrateImuMlTable(report, full_solver_report);
  const ImuTkResult& result = report.result;
  const ImuTkOptions& options = report.options;
  const bool example = IsImuTkExample(report);
  std::ostringstream out;
  out << StringPrintf(
      "calibrate_imu, mode imu_tk: imu_tk's accelerometer calibration (Tedaldi et al., ICRA "
      "2014), g = %.10g m/s^2\n",
      options.gravity_mps2);
  out << LogLine(report);
  out << StringPrintf(
      "initial rest: samples 0..%d (to t = %.10g s, --init_rest_s=%g), variance norm %.6g "
      "(unit^2)\n",
      result.rest_end, report.rest_end_s, options.init_rest_s, result.rest_variance_norm);
  out << StringPrintf("start of every fit: angles 0, gains %g, offsets %.10g (%s)\n\n",
                      options.initial[kTriadGainX], options.initial[kTriadOffsetX],
                      report.initial_offset_from.c_str());
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
  out << StringPrintf(example ? "  %-16s %-14s %-16s" : "  %-16s %-14s %s", "parameter", "unit",
                      "estimate");
  if (example) out << StringPrintf(" %-16s %s", "imu_tk printed", "datasheet");
  out << "\n";
  const auto& infos = TriadParameterInfos();
  for (int p = 0; p < kTriadParameterCount; ++p) {
    std::string value = StringPrintf("%.8g", best.parameters[p]);
    if (p >= kTriadGainX && p <= kTriadGainZ && report.unit == TriadOutputUnit::kCount) {
      value = StringPrintf("1/%.6g", 1.0 / best.parameters[p]);
    }
    out << StringPrintf(example ? "  %-16s %-14s %-16s" : "  %-16s %-14s %s", infos[p].name,
                        TriadParameterUnit(p, report.unit).c_str(), value.c_str());
    if (example) out << StringPrintf(" %-16s %s", kImuTkPrinted[p], kDatasheet[p]);
    out << "\n";
  }
  // Each clause only when it describes the table above: the inverse only for counts, the
  // datasheet only beside imu_tk's own log.
  std::vector<std::string> notes;
  if (report.unit == TriadOutputUnit::kCount)
    notes.push_back("gain_k is printed as 1/(counts per m/s^2), the inverse scale imu_tk prints");
  if (example) notes.push_back("the datasheet gives the misalignment only to 0.01");
  if (!notes.empty()) out << "  (" << JoinStrings(notes, "; ") << ")\n";
  out << "\n";

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
  if (report.has_gyroscope_calibration) out << GyroscopeTable(report, full_solver_report);
  if (!report.imu_tk_calib_acc_path.empty()) {
    out << "\nimu_tk's calibration files (its CalibratedTriad_::save layout): "
        << report.imu_tk_calib_acc_path;
    if (!report.imu_tk_calib_gyro_path.empty())
      out << ", " << report.imu_tk_calib_gyro_path;
    else
      out << " (no gyroscope in the log: no gyroscope file)";
    out << "\n";
  }
  return out.str();
}

nlohmann::json CalibrateImuJson(const CalibrateImuReport& report) {
  if (report.mode == "ml") return CalibrateImuMlJson(report);
  const ImuTkResult& result = report.result;
  const ImuTkOptions& options = report.options;
  const ImuTkSweepEntry& best = result.best();
  nlohmann::json json;
  json["mode"] = "imu_tk";
  json["model"] = "a = T K (u - b), docs/triad.md";
  json["gravity_mps2"] = options.gravity_mps2;
  json["log"] = LogJson(report);
  json["initial_rest"] = {{"duration_s", options.init_rest_s},
                          {"end_sample", result.rest_end},
                          {"end_t_s", report.rest_end_s},
                          {"variance", result.rest_variance},
                          {"variance_norm", result.rest_variance_norm}};
  json["initial_guess"] = {{"gain", options.initial[kTriadGainX]},
                           {"offset", options.initial[kTriadOffsetX]},
                           {"offset_from", report.initial_offset_from}};
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
    units[infos[p].name] = TriadParameterUnit(p, report.unit);
  }
  json["parameters"] = parameters;
  json["units"] = units;
  nlohmann::json inverse;
  for (int k = 0; k < 3; ++k) inverse[Axis(k)] = 1.0 / best.parameters[kTriadGainX + k];
  inverse["unit"] = std::string(TriadOutputUnitName(report.unit)) + "/(m/s^2)";
  json["inverse_gain"] = inverse;
  nlohmann::json intervals = nlohmann::json::array();
  for (size_t i = 0; i < result.intervals.size(); ++i) {
    const StaticInterval& s = result.intervals[i];
    nlohmann::json item = IntervalJson(s);
    item["used"] = static_cast<bool>(result.interval_used[i]);
    intervals.push_back(item);
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
  json["gyroscope"] =
      report.has_gyroscope_calibration ? GyroscopeJson(report) : nlohmann::json(nullptr);
  return json;
}

// The quantisation term of the pose means, when it matters (estimation/triad/triad_pose_noise.h).
std::string QuantisationClause(const CalibrateImuReport& report) {
  const TriadPoseNoise& noise = report.pose_noise;
  if (!noise.quantisation_material) return "";
  const char* unit = TriadOutputUnitName(report.unit);
  return StringPrintf(
      "; plus the output's rounding to its step q = (%.4g, %.4g, %.4g) %s, which the noise "
      "before rounding, sigma = (%.3g, %.3g, %.3g) %s, does not dither away: every pose mean "
      "has variance (%.3g, %.3g, %.3g) %s^2 more that does not average down",
      noise.output_step[0], noise.output_step[1], noise.output_step[2], unit,
      noise.unrounded_stddev[0], noise.unrounded_stddev[1], noise.unrounded_stddev[2], unit,
      noise.quantisation_variance[0], noise.quantisation_variance[1],
      noise.quantisation_variance[2], unit);
}

// The noise model of the pose means in one line.
std::string NoiseModelLine(const CalibrateImuReport& report) {
  const TriadMlResult& ml = report.ml;
  const char* unit = TriadOutputUnitName(report.unit);
  if (!report.allan_noise) {
    return StringPrintf(
        "noise model: white noise, one variance per axis pooled over the poses, s = (%.4g, "
        "%.4g, %.4g) %s; a pose mean of N samples has variance s^2/N%s (--noise)\n",
        std::sqrt(ml.noise_variance[0]), std::sqrt(ml.noise_variance[1]),
        std::sqrt(ml.noise_variance[2]), unit, QuantisationClause(report).c_str());
  }
  const auto& terms = report.pose_noise.terms;
  return StringPrintf(
      "noise model: Allan variance of the poses' samples, per axis N = (%.3g, %.3g, %.3g) "
      "%s/sqrt(Hz), B = (%.3g, %.3g, %.3g) %s, K = (%.3g, %.3g, %.3g) %s sqrt(Hz); a pose mean "
      "of T s has variance N^2/T + 0.441 B^2 + K^2 T/3 (docs/noise.md); white noise rejected "
      "against it (p = %.3g; at tau = %.3g s the Allan variance is (%.3g, %.3g, %.3g) times "
      "white noise's)%s (--noise)\n",
      terms[0].white_density, terms[1].white_density, terms[2].white_density, unit,
      terms[0].bias_instability, terms[1].bias_instability, terms[2].bias_instability, unit,
      terms[0].random_walk, terms[1].random_walk, terms[2].random_walk, unit,
      report.pose_noise.candidate.white_p_value, report.pose_noise.test_tau_s,
      report.pose_noise.avar_ratio[0], report.pose_noise.avar_ratio[1],
      report.pose_noise.avar_ratio[2], QuantisationClause(report).c_str());
}

std::string PosesLine(const CalibrateImuReport& report) {
  const TriadMlResult& ml = report.ml;
  if (report.detector == "imu_tk") {
    return StringPrintf(
               "poses: the %d static intervals of at least %d samples that imu_tk's detector "
               "finds at its chosen k = %d; each pose is the mean of ALL its samples (%d in all)\n",
               ml.pose_count, report.options.interval_samples, report.result.best().multiplier,
               report.ml_sample_count) +
           (report.detector_fallback_reason.empty()
                ? ""
                : "  (imu_tk's detector stood in for the default, the noise floor's, which "
                  "refused: " +
                      report.detector_fallback_reason + ")\n");
  }
  const NoiseFloorDetection& d = report.noise_floor;
  return StringPrintf(
      "poses: the %d static intervals of at least %g s found from the log's own noise floor "
      "(s = %.4g, %.4g, %.4g %s per sample; still where every axis's variance over %d samples "
      "< %g s^2; %.1f%% of the log still; %zu shorter intervals not used%s%s); each pose is the "
      "mean of ALL its samples (%d in all)\n",
      ml.pose_count, report.noise_floor_options.min_interval_s, d.floor_stddev[0],
      d.floor_stddev[1], d.floor_stddev[2], TriadOutputUnitName(report.unit), d.window_samples,
      report.noise_floor_options.threshold_factor, 100.0 * d.still_fraction,
      d.short_intervals.size(),
      d.moving_intervals.empty()
          ? ""
          : StringPrintf("; %zu quiet stretches not used, the output drifting through them",
                         d.moving_intervals.size())
                .c_str(),
      d.rule == kPoseFloorsRule
          ? ("; rule: a floor per pose, s the quietest's, as " + d.rule_reason).c_str()
          : "",
      report.ml_sample_count);
}

std::string CalibrateImuMlTable(const CalibrateImuReport& report, bool full_solver_report) {
  const TriadMlResult& ml = report.ml;
  const bool with_imu_tk = report.imu_tk_status.ok();
  // The datasheet's values beside imu_tk's own example log (recognised by its SHA-256).
  const bool datasheet = with_imu_tk && IsImuTkExample(report);
  std::ostringstream out;
  out << StringPrintf(
      "calibrate_imu, mode ml: maximum likelihood with covariance (docs/triad.md), g = %.10g "
      "m/s^2\n",
      report.ml_options.gravity_mps2);
  out << LogLine(report);
  out << PosesLine(report);
  out << NoiseModelLine(report);
  out << StringPrintf(
      "unknowns: %d parameters + 2 per pose (gravity direction); residuals: 3 per pose; "
      "%d degrees of freedom\n\n",
      kTriadParameterCount + static_cast<int>(ml.effects_estimated.size()), ml.degrees_of_freedom);
  out << "Parameters (a = T K (u - b)), sigma from ceres::Covariance";
  if (report.has_ml_baseline) {
    out << ": the model discovery settled on, its effect terms below the 9; the 9-parameter "
           "fit beside them (baseline)";
  }
  if (with_imu_tk) {
    out << StringPrintf(", beside imu_tk's (its rules, k = %d)\n", report.result.best().multiplier);
    out << StringPrintf("  %-16s %-14s %16s %12s %16s %18s", "parameter", "unit", "ml", "sigma",
                        "imu_tk", "(ml-imu_tk)/sigma");
    out << (datasheet ? "   datasheet\n" : "\n");
  } else {
    out << "\n  imu_tk's rules give no answer on this log: " << report.imu_tk_status.message()
        << "\n";
    out << StringPrintf("  %-16s %-14s %16s %12s\n", "parameter", "unit", "ml", "sigma");
  }
  const auto& infos = TriadParameterInfos();
  for (int p = 0; p < kTriadParameterCount; ++p) {
    out << StringPrintf("  %-16s %-14s %16.8g %12.3g", infos[p].name,
                        TriadParameterUnit(p, report.unit).c_str(), ml.parameters[p], ml.stddev[p]);
    if (report.has_ml_baseline) {
      const double baseline = report.ml_baseline.parameters[p];
      out << StringPrintf("   baseline %.8g (%+.2f sigma)", baseline,
                          (ml.parameters[p] - baseline) / ml.stddev[p]);
    }
    if (with_imu_tk) {
      const double imu_tk = report.result.best().parameters[p];
      out << StringPrintf(" %16.8g %18.2f", imu_tk, (ml.parameters[p] - imu_tk) / ml.stddev[p]);
      if (datasheet) out << "   " << kDatasheet[p];
    }
    out << "\n";
  }
  const std::vector<TriadEffectCoefficient> coefficients = TriadEffectCoefficientList();
  for (const int c : ml.effects_estimated) {
    out << StringPrintf("  %-16s %-14s %16.8g %12.3g  (%.2f sigma from 0)\n",
                        coefficients[c].name.c_str(),
                        TriadEffectUnit(c, TriadOutputUnitName(report.unit)).c_str(), ml.effects[c],
                        ml.effects_stddev[c], ml.effects[c] / ml.effects_stddev[c]);
  }
  out << StringPrintf("  inverse gain (%s per m/s^2):", TriadOutputUnitName(report.unit));
  for (int k = 0; k < 3; ++k) {
    const double gain = ml.parameters[kTriadGainX + k];
    out << StringPrintf(" %c %.6g +- %.2g", "xyz"[k], 1.0 / gain,
                        ml.stddev[kTriadGainX + k] / (gain * gain));
  }
  if (with_imu_tk) {
    const TriadParameters& imu_tk = report.result.best().parameters;
    out << StringPrintf("   (imu_tk: %.6g %.6g %.6g)", 1.0 / imu_tk[kTriadGainX],
                        1.0 / imu_tk[kTriadGainY], 1.0 / imu_tk[kTriadGainZ]);
  }
  out << "\n\n";
  out << PoorlyDeterminedTable(report) << "\n";
  out << "Fit: " << FitDescription(ml, report.allan_noise, report.discovery) << ".\n\n";
  out << TriadDiscoveryTable(report.discovery, report.discovery_options) << "\n";
  out << (full_solver_report ? ml.solver.full_report : ml.solver.brief_report) << "\n";
  if (report.has_gyroscope_ml) out << GyroscopeMlTable(report);
  return out.str();
}

namespace {

// A gyroscope fit as a section: its 12 unknowns and the effect terms it estimated (in the
// block's order, as the file lists them).
Status MakeGyroscopeSection(const GyroscopeMlResult& g, GyroscopeOutputUnit unit,
                            GyroscopeCalibrationSection* section) {
  // The fit's unknowns are the 12, then effects_estimated in its order; the file's, the block's.
  std::vector<int> terms = g.effects_estimated;
  std::sort(terms.begin(), terms.end());
  std::vector<int> order(kGyroscopeCalibrationCount);
  for (int i = 0; i < kGyroscopeCalibrationCount; ++i) order[i] = i;
  for (const int c : terms) {
    const auto at = std::find(g.effects_estimated.begin(), g.effects_estimated.end(), c);
    order.push_back(kGyroscopeCalibrationCount +
                    static_cast<int>(at - g.effects_estimated.begin()));
  }
  const int n = static_cast<int>(order.size());
  Eigen::MatrixXd covariance(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) covariance(i, j) = g.covariance(order[i], order[j]);
  return MakeGyroscopeCalibrationSection(g.parameters, g.offset, terms, g.effects, covariance, unit,
                                         section);
}

}  // namespace

Status AddGyroscopeSection(const CalibrateImuReport& report, CalibrationRecord* record) {
  if (!report.has_gyroscope_ml) return Status::Ok();
  const GyroscopeMlResult& g = report.gyroscope_ml;
  GyroscopeCalibrationSection section;
  ACCELCAL_RETURN_IF_ERROR(MakeGyroscopeSection(g, report.gyroscope_ml_options.unit, &section));
  const GyroscopeDiscoveryResult& d = report.gyroscope_discovery;
  if (!g.effects_estimated.empty()) {
    GyroscopeCalibrationSection baseline;
    ACCELCAL_RETURN_IF_ERROR(
        MakeGyroscopeSection(d.baseline, report.gyroscope_ml_options.unit, &baseline));
    section.baseline.parameter_order = baseline.parameter_order;
    section.baseline.values = baseline.values;
    section.baseline.covariance = baseline.covariance;
  }
  section.fit = {{"method", "maximum likelihood, jointly with the accelerometer's poses"},
                 {"poses", g.rest_means.size()},
                 {"turns", g.turns.size()},
                 {"chi2", g.chi2_gyroscope},
                 {"degrees_of_freedom", g.gyroscope_degrees_of_freedom},
                 {"p_value", g.gyroscope_p_value},
                 {"noise_variance", g.noise_variance},
                 {"bias_wander_variance", g.bias_wander_variance},
                 {"verdict", VerdictCode(d.verdict_code)},
                 {"verdict_text", d.verdict}};
  section.poorly_determined = PoorlyDeterminedJson(d.poorly_determined);
  record->gyroscope = section;
  record->has_gyroscope = true;
  return Status::Ok();
}

CalibrationRecord TriadCalibrationRecord(const CalibrateImuReport& report,
                                         const DataSource& source) {
  const TriadMlResult& ml = report.ml;
  CalibrationRecord record;
  record.geometry = "triad";
  record.output_unit = TriadOutputUnitName(report.unit);
  const std::vector<int> terms = TriadTermsInOrder(ml);
  record.values.resize(kTriadParameterCount + terms.size());
  record.covariance = TriadMlCovariance(ml);
  for (int i = 0; i < kTriadParameterCount; ++i) {
    record.parameter_order.push_back(TriadParameterInfos()[i].name);
    record.values[i] = ml.parameters[i];
  }
  for (size_t a = 0; a < terms.size(); ++a) {
    record.parameter_order.push_back(TriadEffectCoefficientList()[terms[a]].name);
    record.values[kTriadParameterCount + a] = ml.effects[terms[a]];
  }
  if (report.has_ml_baseline) {
    CalibrationBaseline& baseline = record.baseline;
    baseline.parameter_order.assign(record.parameter_order.begin(),
                                    record.parameter_order.begin() + kTriadParameterCount);
    baseline.values.resize(kTriadParameterCount);
    for (int i = 0; i < kTriadParameterCount; ++i)
      baseline.values[i] = report.ml_baseline.parameters[i];
    baseline.covariance = TriadMlCovariance(report.ml_baseline);
  }
  record.gravity_mps2 = report.ml_options.gravity_mps2;
  record.noise_variance.assign(ml.noise_variance.begin(), ml.noise_variance.end());
  record.noise_variance_from =
      report.allan_noise ? "pooled within-pose variances per sample; the fit weighted the pose "
                           "means by the Allan variance of their samples (docs/noise.md)"
                         : "pooled within-pose variances";
  const TriadDiscoveryResult& discovery = report.discovery;
  record.fit = {{"poses", ml.pose_count},
                {"samples", report.ml_sample_count},
                {"chi2", ml.chi2},
                {"dof", ml.degrees_of_freedom},
                {"chi2_p_value", ml.p_value},
                {"noise_model", report.allan_noise ? "allan" : "white"},
                {"description", FitDescription(ml, report.allan_noise, discovery)},
                {"alpha", report.discovery_options.alpha},
                {"verdict_code", VerdictCode(discovery.verdict_code)},
                {"verdict", discovery.verdict}};
  record.poorly_determined = PoorlyDeterminedJson(report.poorly_determined);
  record.source = source;
  return record;
}

nlohmann::json DetectorJson(const CalibrateImuReport& report) {
  if (report.detector == "imu_tk") {
    return {{"name", "imu_tk"},
            {"fallback_from_noise_floor", report.detector_fallback_reason.empty()
                                              ? nlohmann::json(nullptr)
                                              : nlohmann::json(report.detector_fallback_reason)},
            {"chosen_k", report.result.best().multiplier},
            {"window_samples", report.options.window_samples},
            {"interval_samples", report.options.interval_samples}};
  }
  const NoiseFloorDetection& d = report.noise_floor;
  nlohmann::json short_intervals = nlohmann::json::array();
  for (const StaticInterval& s : d.short_intervals) short_intervals.push_back(IntervalJson(s));
  nlohmann::json moving_intervals = nlohmann::json::array();
  for (const StaticInterval& s : d.moving_intervals) moving_intervals.push_back(IntervalJson(s));
  return {{"name", "noise_floor"},
          {"rule", d.rule},
          {"rule_reason", d.rule_reason},
          {"window_samples", d.window_samples},
          {"threshold_factor", report.noise_floor_options.threshold_factor},
          {"min_interval_s", report.noise_floor_options.min_interval_s},
          {"floor_stddev", d.floor_stddev},
          {"threshold_variance", d.threshold_variance},
          {"white_false_alarm", d.white_false_alarm},
          {"still_fraction", d.still_fraction},
          {"floor_shape", d.floor_shape},
          {"short_intervals", short_intervals},
          {"moving_intervals", moving_intervals}};
}

nlohmann::json CalibrateImuMlJson(const CalibrateImuReport& report) {
  const TriadMlResult& ml = report.ml;
  const bool with_imu_tk = report.imu_tk_status.ok();
  const auto& infos = TriadParameterInfos();
  nlohmann::json json;
  json["mode"] = "ml";
  json["model"] = "a = T K (u - b), docs/triad.md";
  json["gravity_mps2"] = report.ml_options.gravity_mps2;
  json["log"] = LogJson(report);
  json["detector"] = DetectorJson(report);
  nlohmann::json parameters, stddev, units, difference, order = nlohmann::json::array();
  for (int p = 0; p < kTriadParameterCount; ++p) {
    parameters[infos[p].name] = ml.parameters[p];
    stddev[infos[p].name] = ml.stddev[p];
    units[infos[p].name] = TriadParameterUnit(p, report.unit);
    if (with_imu_tk) {
      difference[infos[p].name] =
          (ml.parameters[p] - report.result.best().parameters[p]) / ml.stddev[p];
    }
    order.push_back(infos[p].name);
  }
  for (const int c : ml.effects_estimated) {
    const std::string name = TriadEffectCoefficientList()[c].name;
    parameters[name] = ml.effects[c];
    stddev[name] = ml.effects_stddev[c];
    units[name] = TriadEffectUnit(c, TriadOutputUnitName(report.unit));
  }
  json["parameters"] = parameters;
  json["stddev"] = stddev;
  json["units"] = units;
  // The 9 parameters' block (the effect terms' variances are in stddev; the calibration file
  // holds the whole covariance).
  nlohmann::json matrix = nlohmann::json::array();
  for (int i = 0; i < kTriadParameterCount; ++i) matrix.push_back(ml.covariance[i]);
  json["covariance"] = {{"parameter_order", order}, {"matrix", matrix}};
  nlohmann::json terms = nlohmann::json::array();
  for (const int c : TriadTermsInOrder(ml)) terms.push_back(TriadEffectCoefficientList()[c].name);
  json["effect_terms"] = terms;
  json["baseline"] = nullptr;
  if (report.has_ml_baseline) {
    nlohmann::json values, sigmas, baseline_units;
    for (int p = 0; p < kTriadParameterCount; ++p) {
      values[infos[p].name] = report.ml_baseline.parameters[p];
      sigmas[infos[p].name] = report.ml_baseline.stddev[p];
      baseline_units[infos[p].name] = TriadParameterUnit(p, report.unit);
    }
    json["baseline"] = {{"description",
                         "the 9-parameter model's fit of the same poses, before the effect terms "
                         "discovery settled on"},
                        {"parameters", values},
                        {"stddev", sigmas},
                        {"units", baseline_units},
                        {"chi2", report.ml_baseline.chi2},
                        {"dof", report.ml_baseline.degrees_of_freedom}};
  }
  json["chi2"] = ml.chi2;
  json["dof"] = ml.degrees_of_freedom;
  json["chi2_per_dof"] = ml.chi2_per_dof;
  json["chi2_per_dof_expected_spread"] = ml.chi2_per_dof_spread;
  json["p_value"] = ml.p_value;
  json["p_value_definition"] = "P(chi2_dof > chi2), chi2 = sum of squared whitened residuals";
  nlohmann::json allan_terms = nullptr;
  if (report.allan_noise) {
    allan_terms = nlohmann::json::object();
    for (int k = 0; k < 3; ++k) {
      const AllanNoiseTerms& t = report.pose_noise.terms[k];
      allan_terms[Axis(k)] = {{"white_density", t.white_density},
                              {"bias_instability", t.bias_instability},
                              {"random_walk", t.random_walk}};
    }
  }
  json["noise_model"] = {
      {"kind", report.allan_noise ? "allan" : "white"},
      {"description",
       report.allan_noise
           ? "Allan variance of the poses' samples, terms N (unit/sqrt(Hz)), B (unit), K (unit "
             "sqrt(Hz)) per axis; a pose mean of T s has variance N^2/T + 0.441 B^2 + K^2 T/3"
           : "white noise, one variance per axis pooled over the poses; a pose mean of N "
             "samples has variance s^2/N"},
      {"allan_terms", allan_terms},
      {"white_p_value", report.pose_noise.candidate.white_p_value},
      {"stddev_per_sample",
       {std::sqrt(ml.noise_variance[0]), std::sqrt(ml.noise_variance[1]),
        std::sqrt(ml.noise_variance[2])}},
      {"unit", TriadOutputUnitName(report.unit)}};
  if (report.pose_noise.quantisation_material) {
    const TriadPoseNoise& noise = report.pose_noise;
    json["noise_model"]["quantisation"] = {
        {"description",
         "the output's rounding to its step q: every pose mean's variance has B(sigma, q) = "
         "q^2/(2 pi^2) sum_j exp(-4 pi^2 j^2 sigma^2/q^2)/j^2 added, sigma the noise before "
         "rounding"},
        {"step", noise.output_step},
        {"stddev_before_rounding", noise.unrounded_stddev},
        {"pose_mean_variance_added", noise.quantisation_variance}};
  }
  json["fit_description"] = FitDescription(ml, report.allan_noise, report.discovery);
  json["poorly_determined"] = PoorlyDeterminedJson(report.poorly_determined);
  nlohmann::json intervals = nlohmann::json::array();
  for (size_t pose = 0; pose < report.pose_intervals.size(); ++pose) {
    nlohmann::json item = IntervalJson(report.pose_intervals[pose]);
    item["gravity_direction"] = ml.directions[pose];
    item["whitened_residual"] = ml.whitened_residuals[pose];
    intervals.push_back(item);
  }
  json["intervals"] = intervals;
  json["intervals_note"] =
      "the detector's intervals, one per pose, each pose the mean of all its samples; start and "
      "end 0-based, inclusive; mean and noise per axis in the log's unit";
  if (with_imu_tk) {
    const ImuTkSweepEntry& imu_tk = report.result.best();
    nlohmann::json imu_tk_parameters;
    for (int p = 0; p < kTriadParameterCount; ++p)
      imu_tk_parameters[infos[p].name] = imu_tk.parameters[p];
    json["imu_tk"] = {{"parameters", imu_tk_parameters},
                      {"units", units},
                      {"chosen_k", imu_tk.multiplier},
                      {"cost", imu_tk.cost}};
    json["difference_in_sigma"] = difference;
    json["imu_tk_unavailable"] = nullptr;
  } else {
    json["imu_tk"] = nullptr;
    json["imu_tk_unavailable"] = report.imu_tk_status.message();
    json["difference_in_sigma"] = nullptr;
  }
  json["difference_definition"] = "(ml - imu_tk) / ml stddev";
  json["solver"] = ml.solver.brief_report;
  json["discovery"] = TriadDiscoveryJson(report.discovery, report.discovery_options);
  json["verdict"] = VerdictCode(report.discovery.verdict_code);
  json["verdict_text"] = report.discovery.verdict;
  json["gyroscope"] = report.has_gyroscope_ml ? GyroscopeMlJson(report) : nlohmann::json(nullptr);
  return json;
}

}  // namespace accelcal
