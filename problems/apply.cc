// apply: a calibration file applied to a new log, written as corrected accelerations with the
// calibration's uncertainty of each (estimation/tilt_table/calibration_correction.h). The
// calibration's geometry decides the log's layout:
//
//   two_axis (calibrate's): a CSV with the header t,ax,ay (s, m/s^2) or a .mat with t and
//     Aerr; the output's header is t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy
//   triad (calibrate_imu --mode=ml's): a triad log in any layout io/imu_log.h reads
//     (docs/log-layouts.md) in the calibration's output unit; the output's header is
//     t_s,ax_mps2,ay_mps2,az_mps2,sigma_ax_mps2,sigma_ay_mps2,sigma_az_mps2,corr_xy,corr_xz,corr_yz
//     and, when the calibration has a gyroscope section and the log gyroscope columns (in the
//     section's output unit), the angular rate w = T K (u - b) (models/gyroscope.h) after them:
//     gx_radps,gy_radps,gz_radps,sigma_gx_radps,sigma_gy_radps,sigma_gz_radps,corr_gxy,corr_gxz,
//     corr_gyz. Either without the other is said in a '#' line and on stderr, and the
//     accelerometer corrected alone.
//
//   build/bin/apply --calibration=cal.json --in=run.csv --out=corrected.csv
//
// The output CSV starts with '#' lines saying where it came from (the calibration and the log
// with their SHA-256, the command).

#include <gflags/gflags.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include "common/streaming_rank.h"
#include "estimation/tilt_table/calibration_correction.h"
#include "io/atomic_file.h"
#include "io/calibration_file.h"
#include "io/course_data.h"
#include "io/imu_log.h"
#include "io/provenance.h"
#include "problem_support.h"
#include "reporting/apply_checks.h"

// clang-format off
DEFINE_string(calibration, "", "The calibration file (calibrate --calibration_out, or calibrate_imu --mode=ml --calibration_out for a triad and its gyroscope; docs/calibration.md). Required.");
DEFINE_string(in, "", "The log to correct. For a two-axis calibration: CSV with the header t,ax,ay (s, m/s^2) or .mat with t (Mx1, s) and Aerr (Mx2, m/s^2). For a triad calibration: any layout calibrate_imu reads (docs/log-layouts.md; --columns, --rate_hz, --time_unit as there), in the calibration's output unit; its gyroscope columns, if any, in the output unit of the calibration's gyroscope section. Time must increase. Required.");
ACCELCAL_DEFINE_IMU_LOG_FLAGS();
DEFINE_string(out, "", "The corrected CSV to write (atomically), after '#' lines of provenance: t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy (two-axis) or t_s,ax_mps2,ay_mps2,az_mps2,sigma_ax_mps2,sigma_ay_mps2,sigma_az_mps2,corr_xy,corr_xz,corr_yz (triad), then, when the triad's calibration has a gyroscope section and the log gyroscope columns, gx_radps,gy_radps,gz_radps,sigma_gx_radps,sigma_gy_radps,sigma_gz_radps,corr_gxy,corr_gxz,corr_gyz (rad/s; the sigma is the calibration's, not the gyroscope's noise). Required.");
DEFINE_bool(stream, true, "Correct a text log as it is read, writing as it goes: memory independent of the log's length. A .mat log and a pair of files (--gyro_log) are read whole whatever this says; --stream=false reads a text log whole too (the same output, for comparison).");
// clang-format on

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Applies a calibration file to a log. Two-axis (calibrate): per axis\n"
    "a_k = (m_k - bias_k) / (1 + scale_k), m in m/s^2. Triad (calibrate_imu --mode=ml):\n"
    "a = T K (u - b), u in the calibration's output unit (count, m/s^2 or g); and when the\n"
    "file has a gyroscope section and the log gyroscope columns (gx, gy, gz, in the section's\n"
    "output unit: count, rad/s or deg/s), the angular rate w = T_g K_g (u_g - b_g) in rad/s\n"
    "too (columns g*_radps after the accelerometer's). Each corrected value comes with its\n"
    "sigma and correlations, the uncertainty the calibration's covariance gives it (shared by\n"
    "all samples; the sensor's white noise, noise_variance in the calibration file, or the\n"
    "gyroscope's, is not in it). A gyroscope section without gyroscope columns, or columns\n"
    "without a section, is said in a '#' line and on stderr; the accelerometer is corrected.\n"
    "A text log is corrected as it is read (memory does not grow with its length); a .mat log\n"
    "and a pair of files (--gyro_log) are read whole.\n"
    "Exit status: 0 on success, 2 on bad input (one line on stderr; nothing is written).\n\n"
    "  apply --calibration=cal.json --in=run.csv --out=corrected.csv";

Status CheckFlags() {
  if (FLAGS_calibration.empty()) return Status::Error("--calibration must name a calibration file");
  if (FLAGS_in.empty()) return Status::Error("--in must name the log to correct");
  if (FLAGS_out.empty()) return Status::Error("--out must name the CSV to write");
  RunInputs inputs;
  inputs.files = {FLAGS_calibration, FLAGS_in};
  return CheckOutputPaths({{"--out", FLAGS_out}}, inputs);
}

// The '#' lines every output starts with: where it came from.
std::string ProvenanceLines(const DataSource& source) {
  std::string csv = std::string("# accelcal apply ") + AccelcalVersion() +
                    ": accelerations corrected by a calibration (docs/calibration.md)\n";
  for (const auto& [role, file] : source.files) {
    csv += "# " + role + ": " + EscapeForLine(file.path) + " (sha256 " + file.sha256 + ")\n";
  }
  csv += "# command: " + CommandLine() + "\n";
  csv +=
      "# sigma: the calibration's uncertainty of each value, shared by all samples (not the "
      "sensor noise)\n";
  return csv;
}

// The correlation of entries i and j of a covariance, 0 when either variance is 0.
template <typename Matrix>
double CorrelationOf(const Matrix& covariance, int i, int j) {
  const double scale = std::sqrt(covariance(i, i) * covariance(j, j));
  return scale > 0.0 ? covariance(i, j) / scale : 0.0;
}

// A two-axis log's output (read whole: the course's runs are short), its values at full
// precision and their sigma and correlation to 6 significant digits.
std::string CorrectedCsv(const VehicleRun& log, const Eigen::Vector4d& parameters,
                         const Eigen::Matrix4d& covariance, const DataSource& source) {
  std::string csv = ProvenanceLines(source);
  csv += "t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy\n";
  for (int j = 0; j < log.size(); ++j) {
    const CorrectedSample sample =
        CorrectBaseline(parameters, covariance, log.measured_x[j], log.measured_y[j]);
    AppendRoundTripDouble(log.timestamp_s[j], &csv);
    for (int k = 0; k < 2; ++k) {
      csv.push_back(',');
      AppendRoundTripDouble(sample.acceleration[k], &csv);
    }
    for (int k = 0; k < 2; ++k) {
      csv.push_back(',');
      AppendGeneral(std::sqrt(sample.covariance(k, k)), 6, &csv);
    }
    csv.push_back(',');
    AppendGeneral(CorrelationOf(sample.covariance, 0, 1), 6, &csv);
    csv.push_back('\n');
  }
  return csv;
}

// The largest specific force a triad sample may correct to: 10^5 g, beyond the range of shock
// accelerometers (some 10^4 to 10^5 g), let alone of those calibrated by holding them still.
constexpr double kMaxTriadAccelerationMps2 = 1e6;

// The largest angular rate a gyroscope sample may correct to: 10^5 rad/s, some thousand times
// the range of the fastest MEMS gyroscopes (a few thousand deg/s).
constexpr double kMaxAngularRateRadps = 1e5;

// The gyroscope's part of a triad's correction: its calibration when the file has a section
// and the log gyroscope columns; otherwise why not, for a '#' line and a note.
struct GyroscopeUse {
  bool corrected = false;
  GyroscopeCalibrationModel model;  // with its effect terms, when the section carries some
  std::string unit;
  std::string not_used;  // "" when corrected or when there is neither
};

// A sensor's words and range, for the refusal of a damaged sample.
struct SensorRange {
  const char* output;  // "output", "gyroscope output"
  const char* symbol;  // "a", "w"
  const char* unit;    // of the corrected value
  const char* sensor;
  double largest;  // in `unit`
};
constexpr SensorRange kAccelerometerRange = {"output", "a", "m/s^2", "accelerometer",
                                             kMaxTriadAccelerationMps2};
constexpr SensorRange kGyroscopeRange = {"gyroscope output", "w", "rad/s", "gyroscope",
                                         kMaxAngularRateRadps};

// A sample far beyond any sensor's range is a damaged value, not a reading: its square
// overflows the sigma to inf or NaN, and written out it would look like data. Refused, naming
// sample j of the log (at t_s), its output `u` (in `output_unit`) and what it corrects to.
Status CheckInRange(size_t j, double t_s, const std::array<double, 3>& u,
                    const std::string& output_unit, const Eigen::Vector3d& value,
                    const Eigen::Matrix3d& covariance, const SensorRange& range) {
  if (value.allFinite() && covariance.diagonal().allFinite() && value.norm() <= range.largest) {
    return Status::Ok();
  }
  return Status::Error(StringPrintf(
      "%s: sample %zu (t = %.9g s), %s (%.6g, %.6g, %.6g) %s, corrects to |%s| = %.3g %s, beyond "
      "any %s's range (%g %s): a damaged value; remove or repair the sample",
      FLAGS_in.c_str(), j + 1, t_s, range.output, u[0], u[1], u[2], output_unit.c_str(),
      range.symbol, value.norm(), range.unit, range.sensor, range.largest, range.unit));
}

// Sample j's output corrected by the model (its effect terms applied), or why it cannot be.
Status CorrectTriadSample(const TriadCalibrationModel& model, size_t j, double t_s,
                          const std::array<double, 3>& output, CorrectedTriadSample* sample) {
  if (CorrectTriad(model, output, sample)) return Status::Ok();
  return Status::Error(StringPrintf(
      "%s: sample %zu (t = %.9g s), output (%.6g, %.6g, %.6g) %s, has no specific force near "
      "the 9-parameter correction's under %s's effect terms: a damaged value, or a calibration "
      "of another sensor; remove or repair the sample",
      FLAGS_in.c_str(), j + 1, t_s, output[0], output[1], output[2],
      TriadOutputUnitName(model.unit), FLAGS_calibration.c_str()));
}

// The log's gyroscope samples corrected, appended to `samples`; `accelerometer` the log's
// samples corrected (the specific force a g-sensitivity term reads).
Status CorrectGyroscopeLog(const TriadLog& log, const GyroscopeUse& gyroscope,
                           const std::vector<CorrectedTriadSample>& accelerometer,
                           std::vector<CorrectedGyroscopeSample>* samples) {
  samples->reserve(log.size());
  for (size_t j = 0; j < log.size(); ++j) {
    samples->push_back(
        CorrectGyroscope(gyroscope.model, log.gyroscope[j], accelerometer[j].acceleration));
    ACCELCAL_RETURN_IF_ERROR(CheckInRange(j, log.timestamp_s[j], log.gyroscope[j], gyroscope.unit,
                                          samples->back().angular_rate, samples->back().covariance,
                                          kGyroscopeRange));
  }
  return Status::Ok();
}

// Three values, their sigma and their correlations (xy, xz, yz), as CSV fields after a comma,
// appended to `line`: the values at full precision, the sigma and correlations to 9
// significant digits (so that a reader can check them against the calibration's covariance to
// 1e-8). The same bytes as printf's %.17g-or-shorter and %.9g (common/format.h), faster.
void AppendValueSigmaCorrelationFields(const Eigen::Vector3d& value,
                                       const Eigen::Matrix3d& covariance, std::string* line) {
  for (int k = 0; k < 3; ++k) {
    line->push_back(',');
    AppendRoundTripDouble(value[k], line);
  }
  for (int k = 0; k < 3; ++k) {
    line->push_back(',');
    AppendGeneral(std::sqrt(covariance(k, k)), 9, line);
  }
  for (const auto& [i, j] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}}) {
    line->push_back(',');
    AppendGeneral(CorrelationOf(covariance, i, j), 9, line);
  }
}

// One row of a triad's output: t, the accelerometer's fields and, when corrected, the
// gyroscope's.
void AppendTriadRow(double t_s, const CorrectedTriadSample& sample,
                    const CorrectedGyroscopeSample* rate, std::string* csv) {
  AppendRoundTripDouble(t_s, csv);
  AppendValueSigmaCorrelationFields(sample.acceleration, sample.covariance, csv);
  if (rate != nullptr) AppendValueSigmaCorrelationFields(rate->angular_rate, rate->covariance, csv);
  csv->push_back('\n');
}

// The '#' line of the gyroscope: what its columns are, or why there are none.
std::string GyroscopeLine(const GyroscopeUse& gyroscope) {
  if (gyroscope.corrected && gyroscope.model.has_effects()) {
    std::vector<std::string> terms;
    for (const int c : gyroscope.model.effects_in_file)
      terms.push_back(GyroscopeEffectCoefficientName(c));
    return "# gyroscope: g*_radps = T v' - G f (docs/gyroscope.md: the calibration's effect "
           "terms " +
           JoinStrings(terms) +
           " applied, f the corrected a*), the angular rate in rad/s in the accelerometer's "
           "frame, u the log's gyroscope columns in " +
           gyroscope.unit +
           "; sigma_g*_radps and corr_g*: the calibration's uncertainty (its gyroscope section's "
           "covariance), not the gyroscope's white noise\n";
  }
  if (gyroscope.corrected) {
    return "# gyroscope: g*_radps = T K (u - b), the angular rate in rad/s in the "
           "accelerometer's frame, u the log's gyroscope columns in " +
           gyroscope.unit +
           "; sigma_g*_radps and corr_g*: the calibration's uncertainty (its gyroscope section's "
           "12x12 covariance), not the gyroscope's white noise\n";
  }
  return gyroscope.not_used.empty() ? "" : "# gyroscope: " + gyroscope.not_used + "\n";
}

// What the gyroscope's correction leaves out of the calibration's effect terms, and why, as a
// '#' line ("" when it applies all it carries).
std::string GyroscopeTermsLeftOut(const GyroscopeUse& gyroscope) {
  if (!gyroscope.corrected || gyroscope.model.effects_not_applied.empty()) return "";
  std::vector<std::string> terms, why;
  for (const int c : gyroscope.model.effects_not_applied) {
    terms.push_back(GyroscopeEffectCoefficientName(c));
    const char* reason = GyroscopeEffectInfos()[GyroscopeEffectOf(c)].session_only;
    if (std::find(why.begin(), why.end(), reason) == why.end()) why.push_back(reason);
  }
  return "# gyroscope: the calibration's effect terms " + JoinStrings(terms) +
         " are not applied: they belong to the session calibrated (" + JoinStrings(why, "; ") +
         ")\n";
}

// The names of coefficients of the triad's block.
std::string TriadTermList(const std::vector<int>& terms) {
  std::vector<std::string> names;
  for (const int c : terms) names.push_back(TriadEffectCoefficientList()[c].name);
  return JoinStrings(names);
}

// What the accelerometer's correction does with the calibration's effect terms, as a note (""
// when it carries none): those applied, and those carried but left out, and why.
std::string TriadTermsNote(const TriadCalibrationModel& model) {
  std::string note;
  if (model.has_effects()) {
    note = "the calibration's effect terms " + TriadTermList(model.effects_applied) +
           " are applied (a* is the force whose predicted output is the log's, docs/triad.md)";
  }
  if (!model.effects_not_applied.empty()) {
    std::vector<std::string> why;
    for (const int c : model.effects_not_applied) {
      const char* reason = TriadEffectInfos()[TriadEffectCoefficientList()[c].effect].session_only;
      if (std::find(why.begin(), why.end(), reason) == why.end()) why.push_back(reason);
    }
    note += (note.empty() ? "" : "; ") + std::string("the calibration's effect terms ") +
            TriadTermList(model.effects_not_applied) +
            " are not applied: they belong to the session calibrated (" + JoinStrings(why, "; ") +
            ")";
  }
  return note;
}

// A triad's output up to its first row: provenance, the effect terms' and the gyroscope's
// lines, the columns.
std::string TriadHeader(const DataSource& source, const TriadCalibrationModel& model,
                        const GyroscopeUse& gyroscope) {
  const std::string terms = TriadTermsNote(model);
  std::string csv = ProvenanceLines(source) +
                    (terms.empty() ? "" : "# accelerometer: " + terms + "\n") +
                    GyroscopeLine(gyroscope) + GyroscopeTermsLeftOut(gyroscope);
  csv +=
      "t_s,ax_mps2,ay_mps2,az_mps2,sigma_ax_mps2,sigma_ay_mps2,sigma_az_mps2,corr_xy,corr_xz,"
      "corr_yz";
  if (gyroscope.corrected) {
    csv +=
        ",gx_radps,gy_radps,gz_radps,sigma_gx_radps,sigma_gy_radps,sigma_gz_radps,corr_gxy,"
        "corr_gxz,corr_gyz";
  }
  return csv + "\n";
}

// What a triad's summary says of the log: its size and span, its first sample as read and as
// corrected, the median |a|.
struct TriadLogSummary {
  size_t samples = 0;
  double first_t_s = 0.0;
  double last_t_s = 0.0;
  std::array<double, 3> first_output{};
  std::array<double, 3> first_gyroscope{};
  CorrectedTriadSample first;
  CorrectedGyroscopeSample first_rate;
  double median_magnitude = 0.0;
};

std::string TriadSummary(const TriadLogSummary& log, const CalibrationRecord& record,
                         const GyroscopeUse& gyroscope) {
  const CorrectedTriadSample& first = log.first;
  std::string summary = StringPrintf(
      "accelcal apply: %zu triad samples corrected (t %.6g to %.6g s) -> %s\n"
      "  first sample  output (%.8g, %.8g, %.8g) %s -> corrected (%.6g, %.6g, %.6g) m/s^2, "
      "sigma (%.3g, %.3g, %.3g) m/s^2\n"
      "  median |a| over the log %.6g m/s^2 (g = %g)\n",
      log.samples, log.first_t_s, log.last_t_s, FLAGS_out.c_str(), log.first_output[0],
      log.first_output[1], log.first_output[2], record.output_unit.c_str(), first.acceleration.x(),
      first.acceleration.y(), first.acceleration.z(), std::sqrt(first.covariance(0, 0)),
      std::sqrt(first.covariance(1, 1)), std::sqrt(first.covariance(2, 2)), log.median_magnitude,
      record.gravity_mps2);
  if (gyroscope.corrected) {
    const CorrectedGyroscopeSample& rate = log.first_rate;
    summary += StringPrintf(
        "  first sample  gyroscope output (%.8g, %.8g, %.8g) %s -> (%.6g, %.6g, %.6g) rad/s, "
        "sigma (%.3g, %.3g, %.3g) rad/s\n",
        log.first_gyroscope[0], log.first_gyroscope[1], log.first_gyroscope[2],
        gyroscope.unit.c_str(), rate.angular_rate.x(), rate.angular_rate.y(), rate.angular_rate.z(),
        std::sqrt(rate.covariance(0, 0)), std::sqrt(rate.covariance(1, 1)),
        std::sqrt(rate.covariance(2, 2)));
  }
  return summary;
}

// A triad's log held whole (a .mat file, a pair of files, rows ordered by sample number)
// corrected; refused when the corrected magnitudes are not about 1 g. The gyroscope's columns
// too, when `gyroscope` says so.
Status CorrectTriadLog(const TriadLog& log, const TriadCalibrationModel& model,
                       const CalibrationRecord& record, const GyroscopeUse& gyroscope,
                       const DataSource& source, std::string* csv, std::string* summary) {
  std::vector<CorrectedTriadSample> samples(log.size());
  std::vector<double> magnitude;
  magnitude.reserve(log.size());
  // The first refusal of the log's order (the gyroscope's before the accelerometer's, as the
  // streamed path's), once every sample is corrected.
  Status accelerometer_range;
  for (size_t j = 0; j < log.size(); ++j) {
    Status status = CorrectTriadSample(model, j, log.timestamp_s[j], log.output[j], &samples[j]);
    magnitude.push_back(samples[j].acceleration.norm());
    if (status.ok()) {
      status = CheckInRange(j, log.timestamp_s[j], log.output[j], record.output_unit,
                            samples[j].acceleration, samples[j].covariance, kAccelerometerRange);
    }
    if (accelerometer_range.ok()) accelerometer_range = status;
  }
  std::vector<CorrectedGyroscopeSample> rates;
  if (gyroscope.corrected)
    ACCELCAL_RETURN_IF_ERROR(CorrectGyroscopeLog(log, gyroscope, samples, &rates));
  ACCELCAL_RETURN_IF_ERROR(accelerometer_range);
  std::nth_element(magnitude.begin(), magnitude.begin() + magnitude.size() / 2, magnitude.end());
  const double median = magnitude[magnitude.size() / 2];
  ACCELCAL_RETURN_IF_ERROR(CheckMedianMagnitude(FLAGS_in, FLAGS_calibration, median,
                                                record.gravity_mps2, record.output_unit));
  *csv = TriadHeader(source, model, gyroscope);
  for (size_t j = 0; j < log.size(); ++j)
    AppendTriadRow(log.timestamp_s[j], samples[j], gyroscope.corrected ? &rates[j] : nullptr, csv);
  TriadLogSummary described;
  described.samples = log.size();
  described.first_t_s = log.timestamp_s.front();
  described.last_t_s = log.timestamp_s.back();
  described.first_output = log.output.front();
  described.first = samples.front();
  if (gyroscope.corrected) {
    described.first_gyroscope = log.gyroscope.front();
    described.first_rate = rates.front();
  }
  described.median_magnitude = median;
  *summary = TriadSummary(described, record, gyroscope);
  return Status::Ok();
}

// Whether the log's gyroscope is corrected: when the calibration has a section and the log
// gyroscope columns, whose names, when they state a unit, must state the section's.
Status GyroscopeUseOf(const CalibrationRecord& record, bool log_has_gyroscope,
                      const ImuLogSource& log_source, GyroscopeUse* use) {
  if (record.has_gyroscope && !log_has_gyroscope) {
    use->not_used =
        "the calibration's gyroscope section was not used: the log has no gyroscope columns "
        "(gx, gy, gz; docs/log-layouts.md)";
    return Status::Ok();
  }
  if (!record.has_gyroscope && log_has_gyroscope) {
    use->not_used =
        "the log's gyroscope columns were not corrected: the calibration has no gyroscope "
        "section";
    return Status::Ok();
  }
  if (!record.has_gyroscope) return Status::Ok();
  ACCELCAL_RETURN_IF_ERROR(
      GyroscopeCalibrationModelOf(record.gyroscope, &use->model).WithContext(FLAGS_calibration));
  use->unit = GyroscopeOutputUnitName(use->model.unit);
  const std::string& stated = log_source.gyroscope_unit;
  if ((stated == "count" || stated == "rad/s" || stated == "deg/s") && stated != use->unit) {
    return Status::Error(FLAGS_in + ": the gyroscope columns' names say " + stated + ", but " +
                         FLAGS_calibration + "'s gyroscope section is for outputs in " + use->unit +
                         ": give a log in " + use->unit +
                         ", or the calibration of this gyroscope in " + stated);
  }
  use->corrected = true;
  return Status::Ok();
}

// The parameters the calibration file names as poorly determined (docs/calibration.md), in
// one line, or "" when it names none or predates the key; `by` says whose list it is.
std::string PoorlyDeterminedLine(const nlohmann::json& list, const std::string& by) {
  if (!list.is_array() || list.empty()) return "";
  std::string names;
  for (const nlohmann::json& entry : list)
    names += (names.empty() ? "" : ", ") + entry["parameter"].get<std::string>();
  return "  poorly determined by the calibration's " + by + ": " + names + "\n";
}

// The accelerometer's list, and the gyroscope's when its section corrected the log.
std::string PoorlyDeterminedLine(const CalibrationRecord& record, bool gyroscope_corrected) {
  return PoorlyDeterminedLine(record.poorly_determined,
                              "poses (its poorly_determined says why and which poses would "
                              "determine them)") +
         (gyroscope_corrected
              ? PoorlyDeterminedLine(record.gyroscope.poorly_determined,
                                     "session, of the gyroscope (its gyroscope.poorly_determined "
                                     "says why and which turns would determine them)")
              : "");
}

// A log the triad's reader refused (`refusal`) that the two-axis readers take: the course's
// two-axis data (a run of t, ax, ay; a tilt test of theta, ax, ay) given with a triad's
// calibration, said as such rather than as a log without a third axis.
Status TwoAxisDataForATriad(const Status& refusal) {
  VehicleRun run;
  CalibrationTest test;
  const char* what = LoadMeasuredLog(FLAGS_in, &run).ok()        ? "a run: t, ax, ay"
                     : LoadCalibrationTest(FLAGS_in, &test).ok() ? "a tilt test: theta, ax, ay"
                                                                 : nullptr;
  if (what == nullptr) return refusal;
  return Status::Error(FLAGS_in + " is the course's two-axis data (" + what +
                       "), and the calibration is a triad's (x, y, z; " + FLAGS_calibration +
                       "): correct a triad's log with it, or this file with a two-axis "
                       "calibration (calibrate writes one)");
}

// A triad's log read whole (ReadImuLog), corrected and written.
Status ApplyTriadWhole(const CalibrationRecord& record, const TriadCalibrationModel& model,
                       const ImuLogReadOptions& read_options, std::string* summary) {
  TriadLog log;
  ImuLogSource log_source;
  const Status read = ReadImuLog(FLAGS_in, read_options, &log, ImuLogSpacing::kAny, &log_source);
  if (!read.ok()) return TwoAxisDataForATriad(read);
  DataSource source;
  ACCELCAL_RETURN_IF_ERROR(
      DescribeMeasuredData("", {{"calibration", FLAGS_calibration}, {"log", FLAGS_in}}, &source));
  GyroscopeUse gyroscope;
  ACCELCAL_RETURN_IF_ERROR(GyroscopeUseOf(record, log.has_gyroscope(), log_source, &gyroscope));
  std::string csv;
  ACCELCAL_RETURN_IF_ERROR(CorrectTriadLog(log, model, record, gyroscope, source, &csv, summary));
  ACCELCAL_RETURN_IF_ERROR(WriteOutputFiles({{FLAGS_out, csv}}));
  // The notes once the log is corrected, so that a refusal is one line.
  for (const std::string& note : log_source.notes) std::cerr << "apply: note: " << note << "\n";
  if (!TriadTermsNote(model).empty()) std::cerr << "apply: note: " << TriadTermsNote(model) << "\n";
  if (const std::string left_out = GyroscopeTermsLeftOut(gyroscope); !left_out.empty())
    std::cerr << "apply: note: " << left_out.substr(2, left_out.size() - 3) << "\n";
  if (!gyroscope.not_used.empty()) std::cerr << "apply: note: " << gyroscope.not_used << "\n";
  *summary = WithDataLine(source, *summary + PoorlyDeterminedLine(record, gyroscope.corrected));
  return Status::Ok();
}

// Streaming (issue 36, item 2). A text log is corrected batch by batch as it is read and its
// rows written as they come, to a temporary file renamed over --out only when every check has
// passed: memory does not grow with the log. The checks ApplyTriadWhole makes on the whole log
// are made on what the pass counts, with the same outcome: time increases (the reader checks
// it row by row); its median step lies in the range of an IMU log and the median |a| about g
// (a median is outside a range exactly when enough values are, which counting tells); the
// first sample beyond the sensor's range is the one refused (the gyroscope's first, as there).
// The median |a| the summary prints is found exactly by StreamingRankSelector
// (common/streaming_rank.h), in the same pass for a log of up to some two million samples,
// else in one or two more passes that only read and correct. When a check fails on a median,
// the log is read whole after all (ApplyTriadWhole) so that the message states the median: a
// refused log's cost, not a corrected one's. So is a log whose times need the whole log
// (ImuLogSource::times_need_whole_log): rows ordered by sample number, which the reader can only
// sort whole, or host times in bursts timed by a rate fitted to all of them.
constexpr size_t kBatchSamples = 1 << 16;
constexpr size_t kWriteBlockBytes = 1 << 20;

// What the streamed pass knows of the log besides its rows.
struct StreamedTriadPass {
  TriadLogSummary summary;
  bool has_gyroscope = false;
  double previous_t_s = 0.0;
  uint64_t steps_below = 0;  // of [kMinRunStepS, kMaxRunStepS]
  uint64_t steps_above = 0;
  uint64_t magnitudes_below = 0;  // of [0.5 g, 2 g]
  uint64_t magnitudes_above = 0;
  Status gyroscope_use;
  Status gyroscope_range;
  Status accelerometer_range;
  Status write;
  bool read_whole = false;  // a check failed on a median, or the rows need sorting
};

// Whether `count` values beyond a bound put the value of rank `rank` of `size` beyond it.
bool RankBeyond(uint64_t count, uint64_t rank, uint64_t size, bool below) {
  return below ? count >= rank + 1 : count >= size - rank;
}

// The streamed triad path: true in *streamed when it wrote (or refused) the log, false when the
// log must be read whole after all (nothing is written then).
Status ApplyTriadStreamed(const CalibrationRecord& record, const TriadCalibrationModel& model,
                          const ImuLogReadOptions& read_options, std::string* summary,
                          bool* streamed) {
  *streamed = false;
  // The checksums come first in the output, so the log is hashed before it is streamed (a pass
  // at disk speed; the reader then checks that it parses the very bytes hashed). A file the
  // hash cannot read is left to ApplyTriadWhole, which says what the reader says of it.
  DataSource source;
  if (!DescribeMeasuredData("", {{"calibration", FLAGS_calibration}, {"log", FLAGS_in}}, &source)
           .ok()) {
    return Status::Ok();
  }
  const double gravity = record.gravity_mps2;
  StreamedTriadPass pass;
  StreamingRankSelector median(0.5 * gravity, 2.0 * gravity);
  GyroscopeUse gyroscope;
  ImuLogSource log_source;
  Status read;
  const Status written = WriteFileAtomicallyStreamed(FLAGS_out, [&](const AppendFunction& append) {
    std::string block;
    size_t& j = pass.summary.samples;
    read = StreamImuLog(
        FLAGS_in, read_options, kBatchSamples,
        [&](const TriadLog& batch) {
          if (j == 0) {
            pass.has_gyroscope = batch.has_gyroscope();
            pass.gyroscope_use = GyroscopeUseOf(record, pass.has_gyroscope, log_source, &gyroscope);
            block = TriadHeader(source, model, gyroscope);
          }
          for (size_t i = 0; i < batch.size(); ++i, ++j) {
            const double t_s = batch.timestamp_s[i];
            if (j > 0) {
              const double step = t_s - pass.previous_t_s;
              pass.steps_below += step < kMinRunStepS ? 1 : 0;
              pass.steps_above += step > kMaxRunStepS ? 1 : 0;
            }
            pass.previous_t_s = t_s;
            if (!pass.gyroscope_use.ok() || !pass.gyroscope_range.ok()) continue;
            CorrectedTriadSample sample;
            if (pass.accelerometer_range.ok()) {
              pass.accelerometer_range =
                  CorrectTriadSample(model, j, t_s, batch.output[i], &sample);
            }
            const double magnitude = sample.acceleration.norm();
            median.Add(magnitude);
            pass.magnitudes_below += magnitude < 0.5 * gravity ? 1 : 0;
            pass.magnitudes_above += magnitude > 2.0 * gravity ? 1 : 0;
            if (pass.accelerometer_range.ok()) {
              pass.accelerometer_range =
                  CheckInRange(j, t_s, batch.output[i], record.output_unit, sample.acceleration,
                               sample.covariance, kAccelerometerRange);
            }
            CorrectedGyroscopeSample rate;
            if (gyroscope.corrected) {
              rate = CorrectGyroscope(gyroscope.model, batch.gyroscope[i], sample.acceleration);
              pass.gyroscope_range =
                  CheckInRange(j, t_s, batch.gyroscope[i], gyroscope.unit, rate.angular_rate,
                               rate.covariance, kGyroscopeRange);
            }
            if (j == 0) {
              pass.summary.first_t_s = t_s;
              pass.summary.first_output = batch.output[i];
              pass.summary.first = sample;
              if (gyroscope.corrected) {
                pass.summary.first_gyroscope = batch.gyroscope[i];
                pass.summary.first_rate = rate;
              }
            }
            if (!pass.accelerometer_range.ok() || !pass.gyroscope_range.ok() || !pass.write.ok())
              continue;
            AppendTriadRow(t_s, sample, gyroscope.corrected ? &rate : nullptr, &block);
            if (block.size() >= kWriteBlockBytes) {
              pass.write = append(block);
              block.clear();
            }
          }
          pass.summary.last_t_s = pass.previous_t_s;
        },
        &log_source);
    if (log_source.times_need_whole_log) {
      pass.read_whole = true;
      return Status::Error("the rows are sorted whole");
    }
    if (!read.ok()) return TwoAxisDataForATriad(read);
    const uint64_t samples = pass.summary.samples;
    if (samples < 2 || RankBeyond(pass.steps_below, (samples - 1) / 2, samples - 1, true) ||
        RankBeyond(pass.steps_above, (samples - 1) / 2, samples - 1, false)) {
      pass.read_whole = true;
      return Status::Error("the time checks fail");
    }
    ACCELCAL_RETURN_IF_ERROR(pass.gyroscope_use);
    ACCELCAL_RETURN_IF_ERROR(pass.gyroscope_range);
    ACCELCAL_RETURN_IF_ERROR(pass.accelerometer_range);
    if (RankBeyond(pass.magnitudes_below, samples / 2, samples, true) ||
        RankBeyond(pass.magnitudes_above, samples / 2, samples, false)) {
      pass.read_whole = true;
      return Status::Error("the median |a| is not about g");
    }
    ACCELCAL_RETURN_IF_ERROR(pass.write);
    ACCELCAL_RETURN_IF_ERROR(append(block));
    // The median |a| exactly, in further passes when the first could not hold its candidates.
    while (!median.FinishPass(samples / 2)) {
      ACCELCAL_RETURN_IF_ERROR(StreamImuLog(
          FLAGS_in, read_options, kBatchSamples,
          [&](const TriadLog& batch) {
            for (const std::array<double, 3>& output : batch.output) {
              CorrectedTriadSample sample;
              CorrectTriad(model, output, &sample);  // every sample settled in the first pass
              median.Add(sample.acceleration.norm());
            }
          },
          nullptr));
    }
    pass.summary.median_magnitude = median.value();
    return Status::Ok();
  });
  if (pass.read_whole) return Status::Ok();
  ACCELCAL_RETURN_IF_ERROR(written);
  *streamed = true;
  // The notes once the log is corrected, so that a refusal is one line.
  for (const std::string& note : log_source.notes) std::cerr << "apply: note: " << note << "\n";
  if (!gyroscope.not_used.empty()) std::cerr << "apply: note: " << gyroscope.not_used << "\n";
  if (!TriadTermsNote(model).empty()) std::cerr << "apply: note: " << TriadTermsNote(model) << "\n";
  if (const std::string left_out = GyroscopeTermsLeftOut(gyroscope); !left_out.empty())
    std::cerr << "apply: note: " << left_out.substr(2, left_out.size() - 3) << "\n";
  *summary = WithDataLine(source, TriadSummary(pass.summary, record, gyroscope) +
                                      PoorlyDeterminedLine(record, gyroscope.corrected));
  return Status::Ok();
}

// The triad path of Run: its own log layout and output columns.
Status ApplyTriad(const CalibrationRecord& record, std::string* summary) {
  TriadCalibrationModel model;
  ACCELCAL_RETURN_IF_ERROR(TriadCalibrationModelOf(record, FLAGS_calibration, &model));
  ImuLogReadOptions read_options;
  ACCELCAL_RETURN_IF_ERROR(ACCELCAL_IMU_LOG_OPTIONS(&read_options));
  if (FLAGS_stream && StreamsLikeReadImuLog(FLAGS_in, read_options)) {
    bool streamed = false;
    ACCELCAL_RETURN_IF_ERROR(ApplyTriadStreamed(record, model, read_options, summary, &streamed));
    if (streamed) return Status::Ok();
  }
  return ApplyTriadWhole(record, model, read_options, summary);
}

std::string Summary(const VehicleRun& log, const Eigen::Vector4d& parameters,
                    const Eigen::Matrix4d& covariance) {
  const CorrectedSample first =
      CorrectBaseline(parameters, covariance, log.measured_x[0], log.measured_y[0]);
  return StringPrintf(
      "accelcal apply: %d samples corrected (t %.6g to %.6g s) -> %s\n"
      "  first sample  measured (%.6g, %.6g) -> corrected (%.6g, %.6g) m/s^2, "
      "sigma (%.3g, %.3g) m/s^2\n",
      log.size(), log.timestamp_s.front(), log.timestamp_s.back(), FLAGS_out.c_str(),
      log.measured_x[0], log.measured_y[0], first.acceleration.x(), first.acceleration.y(),
      std::sqrt(first.covariance(0, 0)), std::sqrt(first.covariance(1, 1)));
}

int Run(int argc, char** argv) {
  if (!InitProblem("apply", kUsage, "problems/apply", &argc, &argv)) return kExitBadInput;
  Status status = CheckFlags();
  CalibrationRecord record;
  if (status.ok()) status = ReadCalibrationFile(FLAGS_calibration, &record);
  if (status.ok() && record.geometry == "triad") {
    std::string summary;
    status = ApplyTriad(record, &summary);
    if (!status.ok()) return ExitWithError("apply", status);
    std::cout << summary << std::flush;
    return 0;
  }
  Eigen::Vector4d parameters;
  Eigen::Matrix4d covariance;
  if (status.ok()) status = TwoAxisBaseline(record, FLAGS_calibration, &parameters, &covariance);
  VehicleRun log;
  std::vector<std::string> notes;
  if (status.ok()) status = LoadMeasuredLog(FLAGS_in, &log, &notes);
  DataSource source;
  if (status.ok()) {
    status =
        DescribeMeasuredData("", {{"calibration", FLAGS_calibration}, {"log", FLAGS_in}}, &source);
  }
  std::string csv;
  if (status.ok()) csv = CorrectedCsv(log, parameters, covariance, source);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_out, csv}});
  if (!status.ok()) return ExitWithError("apply", status);
  PrintInputNotes(notes);
  std::cout << WithDataLine(source, Summary(log, parameters, covariance)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("apply", accelcal::Run, argc, argv);
}
