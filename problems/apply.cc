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

#include "estimation/tilt_table/calibration_correction.h"
#include "io/calibration_file.h"
#include "io/course_data.h"
#include "io/imu_log.h"
#include "io/provenance.h"
#include "problem_support.h"

// clang-format off
DEFINE_string(calibration, "", "The calibration file (calibrate --calibration_out, or calibrate_imu --mode=ml --calibration_out for a triad and its gyroscope; docs/calibration.md). Required.");
DEFINE_string(in, "", "The log to correct. For a two-axis calibration: CSV with the header t,ax,ay (s, m/s^2) or .mat with t (Mx1, s) and Aerr (Mx2, m/s^2). For a triad calibration: any layout calibrate_imu reads (docs/log-layouts.md; --columns, --rate_hz, --time_unit as there), in the calibration's output unit; its gyroscope columns, if any, in the output unit of the calibration's gyroscope section. Time must increase. Required.");
ACCELCAL_DEFINE_IMU_LOG_FLAGS();
DEFINE_string(out, "", "The corrected CSV to write (atomically), after '#' lines of provenance: t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy (two-axis) or t_s,ax_mps2,ay_mps2,az_mps2,sigma_ax_mps2,sigma_ay_mps2,sigma_az_mps2,corr_xy,corr_xz,corr_yz (triad), then, when the triad's calibration has a gyroscope section and the log gyroscope columns, gx_radps,gy_radps,gz_radps,sigma_gx_radps,sigma_gy_radps,sigma_gz_radps,corr_gxy,corr_gxz,corr_gyz (rad/s; the sigma is the calibration's, not the gyroscope's noise). Required.");
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
    csv += "# " + role + ": " + file.path + " (sha256 " + file.sha256 + ")\n";
  }
  csv += "# command: " + CommandLine() + "\n";
  csv +=
      "# sigma: the calibration's uncertainty of each value, shared by all samples (not the "
      "sensor noise)\n";
  return csv;
}

// The correlation of values i and j, `format`ted.
std::string Correlation(const Eigen::MatrixXd& covariance, int i, int j,
                        const char* format = "%.6g") {
  const double scale = std::sqrt(covariance(i, i) * covariance(j, j));
  return StringPrintf(format, scale > 0.0 ? covariance(i, j) / scale : 0.0);
}

std::string CorrectedCsv(const VehicleRun& log, const Eigen::Vector4d& parameters,
                         const Eigen::Matrix4d& covariance, const DataSource& source) {
  std::string csv = ProvenanceLines(source);
  csv += "t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy\n";
  for (int j = 0; j < log.size(); ++j) {
    const CorrectedSample sample =
        CorrectBaseline(parameters, covariance, log.measured_x[j], log.measured_y[j]);
    csv += RoundTripDouble(log.timestamp_s[j]) + "," + RoundTripDouble(sample.acceleration.x()) +
           "," + RoundTripDouble(sample.acceleration.y()) + "," +
           StringPrintf("%.6g", std::sqrt(sample.covariance(0, 0))) + "," +
           StringPrintf("%.6g", std::sqrt(sample.covariance(1, 1))) + "," +
           Correlation(sample.covariance, 0, 1) + "\n";
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
  GyroscopeParameters parameters{};
  GyroscopeOffset offset{};
  Eigen::MatrixXd covariance;
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
// sample j of the log, its output `u` (in `output_unit`) and what it corrects to.
Status CheckInRange(const TriadLog& log, size_t j, const std::array<double, 3>& u,
                    const std::string& output_unit, const Eigen::Vector3d& value,
                    const Eigen::Matrix3d& covariance, const SensorRange& range) {
  if (value.allFinite() && covariance.diagonal().allFinite() && value.norm() <= range.largest) {
    return Status::Ok();
  }
  return Status::Error(StringPrintf(
      "%s: sample %zu (t = %.9g s), %s (%.6g, %.6g, %.6g) %s, corrects to |%s| = %.3g %s, beyond "
      "any %s's range (%g %s): a damaged value; remove or repair the sample",
      FLAGS_in.c_str(), j + 1, log.timestamp_s[j], range.output, u[0], u[1], u[2],
      output_unit.c_str(), range.symbol, value.norm(), range.unit, range.sensor, range.largest,
      range.unit));
}

// The log's gyroscope samples corrected, appended to `samples`.
Status CorrectGyroscopeLog(const TriadLog& log, const GyroscopeUse& gyroscope,
                           std::vector<CorrectedGyroscopeSample>* samples) {
  samples->reserve(log.size());
  for (size_t j = 0; j < log.size(); ++j) {
    samples->push_back(CorrectGyroscope(gyroscope.parameters, gyroscope.offset,
                                        gyroscope.covariance, log.gyroscope[j]));
    ACCELCAL_RETURN_IF_ERROR(CheckInRange(log, j, log.gyroscope[j], gyroscope.unit,
                                          samples->back().angular_rate, samples->back().covariance,
                                          kGyroscopeRange));
  }
  return Status::Ok();
}

// Three values, their sigma and their correlations (xy, xz, yz), as CSV fields after a comma:
// the values at full precision, the sigma and correlations to 9 significant digits (so that a
// reader can check them against the calibration's covariance to 1e-8).
std::string ValueSigmaCorrelationFields(const Eigen::Vector3d& value,
                                        const Eigen::Matrix3d& covariance) {
  std::string fields;
  for (int k = 0; k < 3; ++k) fields += "," + RoundTripDouble(value[k]);
  for (int k = 0; k < 3; ++k) fields += StringPrintf(",%.9g", std::sqrt(covariance(k, k)));
  return fields + "," + Correlation(covariance, 0, 1, "%.9g") + "," +
         Correlation(covariance, 0, 2, "%.9g") + "," + Correlation(covariance, 1, 2, "%.9g");
}

// The '#' line of the gyroscope: what its columns are, or why there are none.
std::string GyroscopeLine(const GyroscopeUse& gyroscope) {
  if (gyroscope.corrected) {
    return "# gyroscope: g*_radps = T K (u - b), the angular rate in rad/s in the "
           "accelerometer's frame, u the log's gyroscope columns in " +
           gyroscope.unit +
           "; sigma_g*_radps and corr_g*: the calibration's uncertainty (its gyroscope section's "
           "12x12 covariance), not the gyroscope's white noise\n";
  }
  return gyroscope.not_used.empty() ? "" : "# gyroscope: " + gyroscope.not_used + "\n";
}

// A triad's log corrected; refused when the corrected magnitudes are not about 1 g, which an
// accelerometer's are at rest and in ordinary motion: the log is then in another unit than
// the calibration's, or from another sensor. The gyroscope's columns too, when `gyroscope`
// says so.
Status CorrectTriadLog(const TriadLog& log, const TriadParameters& parameters,
                       const Eigen::MatrixXd& covariance, const CalibrationRecord& record,
                       const GyroscopeUse& gyroscope, const DataSource& source, std::string* csv,
                       std::string* summary) {
  std::vector<CorrectedTriadSample> samples;
  samples.reserve(log.size());
  std::vector<double> magnitude;
  magnitude.reserve(log.size());
  std::vector<CorrectedGyroscopeSample> rates;
  if (gyroscope.corrected) ACCELCAL_RETURN_IF_ERROR(CorrectGyroscopeLog(log, gyroscope, &rates));
  for (size_t j = 0; j < log.size(); ++j) {
    samples.push_back(CorrectTriad(parameters, covariance, log.output[j]));
    magnitude.push_back(samples.back().acceleration.norm());
    ACCELCAL_RETURN_IF_ERROR(CheckInRange(log, j, log.output[j], record.output_unit,
                                          samples.back().acceleration, samples.back().covariance,
                                          kAccelerometerRange));
  }
  std::nth_element(magnitude.begin(), magnitude.begin() + magnitude.size() / 2, magnitude.end());
  const double median = magnitude[magnitude.size() / 2];
  if (!(median >= 0.5 * record.gravity_mps2 && median <= 2.0 * record.gravity_mps2)) {
    return Status::Error(StringPrintf(
        "%s: corrected by %s, the log's median |a| is %.4g m/s^2, not about g = %g: is the log "
        "in the calibration's output unit (%s) and from the same sensor?",
        FLAGS_in.c_str(), FLAGS_calibration.c_str(), median, record.gravity_mps2,
        record.output_unit.c_str()));
  }
  *csv = ProvenanceLines(source) + GyroscopeLine(gyroscope);
  *csv +=
      "t_s,ax_mps2,ay_mps2,az_mps2,sigma_ax_mps2,sigma_ay_mps2,sigma_az_mps2,corr_xy,corr_xz,"
      "corr_yz";
  if (gyroscope.corrected) {
    *csv +=
        ",gx_radps,gy_radps,gz_radps,sigma_gx_radps,sigma_gy_radps,sigma_gz_radps,corr_gxy,"
        "corr_gxz,corr_gyz";
  }
  *csv += "\n";
  for (size_t j = 0; j < log.size(); ++j) {
    *csv += RoundTripDouble(log.timestamp_s[j]) +
            ValueSigmaCorrelationFields(samples[j].acceleration, samples[j].covariance);
    if (gyroscope.corrected)
      *csv += ValueSigmaCorrelationFields(rates[j].angular_rate, rates[j].covariance);
    *csv += "\n";
  }
  const CorrectedTriadSample& first = samples.front();
  *summary = StringPrintf(
      "accelcal apply: %zu triad samples corrected (t %.6g to %.6g s) -> %s\n"
      "  first sample  output (%.8g, %.8g, %.8g) %s -> corrected (%.6g, %.6g, %.6g) m/s^2, "
      "sigma (%.3g, %.3g, %.3g) m/s^2\n"
      "  median |a| over the log %.6g m/s^2 (g = %g)\n",
      log.size(), log.timestamp_s.front(), log.timestamp_s.back(), FLAGS_out.c_str(),
      log.output[0][0], log.output[0][1], log.output[0][2], record.output_unit.c_str(),
      first.acceleration.x(), first.acceleration.y(), first.acceleration.z(),
      std::sqrt(first.covariance(0, 0)), std::sqrt(first.covariance(1, 1)),
      std::sqrt(first.covariance(2, 2)), median, record.gravity_mps2);
  if (gyroscope.corrected) {
    const CorrectedGyroscopeSample& rate = rates.front();
    *summary += StringPrintf(
        "  first sample  gyroscope output (%.8g, %.8g, %.8g) %s -> (%.6g, %.6g, %.6g) rad/s, "
        "sigma (%.3g, %.3g, %.3g) rad/s\n",
        log.gyroscope[0][0], log.gyroscope[0][1], log.gyroscope[0][2], gyroscope.unit.c_str(),
        rate.angular_rate.x(), rate.angular_rate.y(), rate.angular_rate.z(),
        std::sqrt(rate.covariance(0, 0)), std::sqrt(rate.covariance(1, 1)),
        std::sqrt(rate.covariance(2, 2)));
  }
  return Status::Ok();
}

// Whether the log's gyroscope is corrected: when the calibration has a section and the log
// gyroscope columns, whose names, when they state a unit, must state the section's.
Status GyroscopeUseOf(const CalibrationRecord& record, const TriadLog& log,
                      const ImuLogSource& log_source, GyroscopeUse* use) {
  if (record.has_gyroscope && !log.has_gyroscope()) {
    use->not_used =
        "the calibration's gyroscope section was not used: the log has no gyroscope columns "
        "(gx, gy, gz; docs/log-layouts.md)";
    return Status::Ok();
  }
  if (!record.has_gyroscope && log.has_gyroscope()) {
    use->not_used =
        "the log's gyroscope columns were not corrected: the calibration has no gyroscope "
        "section";
    return Status::Ok();
  }
  if (!record.has_gyroscope) return Status::Ok();
  GyroscopeOutputUnit unit;
  ACCELCAL_RETURN_IF_ERROR(GyroscopeCalibration(record.gyroscope, &use->parameters, &use->offset,
                                                &use->covariance, &unit)
                               .WithContext(FLAGS_calibration));
  use->unit = GyroscopeOutputUnitName(unit);
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
// one line, or "" when it names none or predates the key.
std::string PoorlyDeterminedLine(const CalibrationRecord& record) {
  if (!record.poorly_determined.is_array() || record.poorly_determined.empty()) return "";
  std::string names;
  for (const nlohmann::json& entry : record.poorly_determined)
    names += (names.empty() ? "" : ", ") + entry["parameter"].get<std::string>();
  return "  poorly determined by the calibration's poses (its poorly_determined says why and "
         "which poses would determine them): " +
         names + "\n";
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

// The triad path of Run: its own log layout and output columns.
Status ApplyTriad(const CalibrationRecord& record, std::string* summary) {
  TriadParameters parameters;
  Eigen::MatrixXd covariance;
  TriadOutputUnit unit;
  ACCELCAL_RETURN_IF_ERROR(
      TriadCalibration(record, FLAGS_calibration, &parameters, &covariance, &unit));
  ImuLogReadOptions read_options;
  ACCELCAL_RETURN_IF_ERROR(ACCELCAL_IMU_LOG_OPTIONS(&read_options));
  TriadLog log;
  ImuLogSource log_source;
  const Status read = ReadImuLog(FLAGS_in, read_options, &log, ImuLogSpacing::kAny, &log_source);
  if (!read.ok()) return TwoAxisDataForATriad(read);
  DataSource source;
  ACCELCAL_RETURN_IF_ERROR(
      DescribeMeasuredData("", {{"calibration", FLAGS_calibration}, {"log", FLAGS_in}}, &source));
  GyroscopeUse gyroscope;
  ACCELCAL_RETURN_IF_ERROR(GyroscopeUseOf(record, log, log_source, &gyroscope));
  std::string csv;
  ACCELCAL_RETURN_IF_ERROR(
      CorrectTriadLog(log, parameters, covariance, record, gyroscope, source, &csv, summary));
  ACCELCAL_RETURN_IF_ERROR(WriteOutputFiles({{FLAGS_out, csv}}));
  // The notes once the log is corrected, so that a refusal is one line.
  for (const std::string& note : log_source.notes) std::cerr << "apply: note: " << note << "\n";
  if (!gyroscope.not_used.empty()) std::cerr << "apply: note: " << gyroscope.not_used << "\n";
  *summary = WithDataLine(source, *summary + PoorlyDeterminedLine(record));
  return Status::Ok();
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
