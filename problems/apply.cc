// apply: a calibration file applied to a new log, written as corrected accelerations with the
// calibration's uncertainty of each (estimation/tilt_table/calibration_correction.h). The
// calibration's geometry decides the log's layout:
//
//   two_axis (calibrate's): a CSV with the header t,ax,ay (s, m/s^2) or a .mat with t and
//     Aerr; the output's header is t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy
//   triad (calibrate_imu --mode=ml's): a triad log in any layout io/imu_log.h reads
//     (docs/log-layouts.md) in the calibration's output unit; the output's header is
//     t_s,ax_mps2,ay_mps2,az_mps2,sigma_ax_mps2,sigma_ay_mps2,sigma_az_mps2,corr_xy,corr_xz,corr_yz
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
DEFINE_string(calibration, "", "The calibration file (calibrate --calibration_out). Required.");
DEFINE_string(in, "", "The log to correct. For a two-axis calibration: CSV with the header t,ax,ay (s, m/s^2) or .mat with t (Mx1, s) and Aerr (Mx2, m/s^2). For a triad calibration: any layout calibrate_imu reads (docs/log-layouts.md; --columns, --rate_hz, --time_unit as there), in the calibration's output unit. Time must increase. Required.");
ACCELCAL_DEFINE_IMU_LOG_FLAGS();
DEFINE_string(out, "", "The corrected CSV to write (atomically), after '#' lines of provenance: t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy (two-axis) or t_s,ax_mps2,ay_mps2,az_mps2,sigma_ax_mps2,sigma_ay_mps2,sigma_az_mps2,corr_xy,corr_xz,corr_yz (triad). Required.");
// clang-format on

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Applies a calibration file to a log. Two-axis (calibrate): per axis\n"
    "a_k = (m_k - bias_k) / (1 + scale_k), m in m/s^2. Triad (calibrate_imu --mode=ml):\n"
    "a = T K (u - b), u in the calibration's output unit (count, m/s^2 or g). Each corrected\n"
    "value (m/s^2) comes with its sigma and correlations, the uncertainty the calibration's\n"
    "covariance gives it (shared by all samples; the sensor's white noise, noise_variance in\n"
    "the calibration file, is not in it).\n"
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

std::string Correlation(const Eigen::MatrixXd& covariance, int i, int j) {
  const double scale = std::sqrt(covariance(i, i) * covariance(j, j));
  return StringPrintf("%.6g", scale > 0.0 ? covariance(i, j) / scale : 0.0);
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

// A triad's log corrected; refused when the corrected magnitudes are not about 1 g, which an
// accelerometer's are at rest and in ordinary motion: the log is then in another unit than
// the calibration's, or from another sensor.
Status CorrectTriadLog(const TriadLog& log, const TriadParameters& parameters,
                       const Eigen::MatrixXd& covariance, const CalibrationRecord& record,
                       const DataSource& source, std::string* csv, std::string* summary) {
  std::vector<CorrectedTriadSample> samples;
  samples.reserve(log.size());
  std::vector<double> magnitude;
  magnitude.reserve(log.size());
  for (size_t j = 0; j < log.size(); ++j) {
    samples.push_back(CorrectTriad(parameters, covariance, log.output[j]));
    magnitude.push_back(samples.back().acceleration.norm());
    // A sample far beyond any accelerometer's range is a damaged value, not a reading: its
    // square overflows the sigma to inf or NaN, and written out it would look like data.
    const bool finite =
        samples.back().acceleration.allFinite() && samples.back().covariance.diagonal().allFinite();
    if (!finite || magnitude.back() > kMaxTriadAccelerationMps2) {
      const std::array<double, 3>& u = log.output[j];
      return Status::Error(StringPrintf(
          "%s: sample %zu (t = %.9g s), output (%.6g, %.6g, %.6g) %s, corrects to |a| = %.3g "
          "m/s^2, beyond any accelerometer's range (%g m/s^2): a damaged value; remove or "
          "repair the sample",
          FLAGS_in.c_str(), j + 1, log.timestamp_s[j], u[0], u[1], u[2], record.output_unit.c_str(),
          magnitude.back(), kMaxTriadAccelerationMps2));
    }
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
  *csv = ProvenanceLines(source);
  *csv +=
      "t_s,ax_mps2,ay_mps2,az_mps2,sigma_ax_mps2,sigma_ay_mps2,sigma_az_mps2,corr_xy,corr_xz,"
      "corr_yz\n";
  for (size_t j = 0; j < log.size(); ++j) {
    const CorrectedTriadSample& sample = samples[j];
    *csv += RoundTripDouble(log.timestamp_s[j]);
    for (int k = 0; k < 3; ++k) *csv += "," + RoundTripDouble(sample.acceleration[k]);
    for (int k = 0; k < 3; ++k) *csv += StringPrintf(",%.6g", std::sqrt(sample.covariance(k, k)));
    *csv += "," + Correlation(sample.covariance, 0, 1) + "," +
            Correlation(sample.covariance, 0, 2) + "," + Correlation(sample.covariance, 1, 2) +
            "\n";
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
  ACCELCAL_RETURN_IF_ERROR(
      ReadImuLog(FLAGS_in, read_options, &log, ImuLogSpacing::kAny, &log_source));
  for (const std::string& note : log_source.notes) std::cerr << "apply: note: " << note << "\n";
  DataSource source;
  ACCELCAL_RETURN_IF_ERROR(
      DescribeMeasuredData("", {{"calibration", FLAGS_calibration}, {"log", FLAGS_in}}, &source));
  std::string csv;
  ACCELCAL_RETURN_IF_ERROR(
      CorrectTriadLog(log, parameters, covariance, record, source, &csv, summary));
  ACCELCAL_RETURN_IF_ERROR(WriteOutputFiles({{FLAGS_out, csv}}));
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
