// apply: a calibration file (calibrate's, io/calibration_file.h) applied to a new log of
// measured accelerations, written as corrected accelerations with the calibration's
// uncertainty of each (estimation/calibration_correction.h).
//
//   build/bin/apply --calibration=cal.json --in=run.csv --out=corrected.csv
//
// The log is the run's layout: a CSV with the header t,ax,ay (s, m/s^2) or a .mat with t and
// Aerr. The output CSV starts with '#' lines saying where it came from (the calibration and
// the log with their SHA-256, the command), then the header
//   t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy

#include <gflags/gflags.h>

#include <iostream>

#include "estimation/calibration_correction.h"
#include "io/calibration_file.h"
#include "io/course_data.h"
#include "io/provenance.h"
#include "problem_support.h"

// clang-format off
DEFINE_string(calibration, "", "The calibration file (calibrate --calibration_out). Required.");
DEFINE_string(in, "", "The log to correct: CSV with the header t,ax,ay (s, m/s^2) or .mat with t (Mx1, s) and Aerr (Mx2, m/s^2). Time must increase. Required.");
DEFINE_string(out, "", "The corrected CSV to write (atomically): t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy after '#' lines of provenance. Required.");
// clang-format on

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Applies a calibration file to a log of measured accelerations (m/s^2): per axis\n"
    "a_k = (m_k - bias_k) / (1 + scale_k), with sigma_ak and corr(a_x, a_y), the uncertainty\n"
    "the calibration's covariance gives each corrected value (shared by all samples; the\n"
    "sensor's white noise, noise_variance in the calibration file, is not in it).\n"
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

std::string CorrectedCsv(const VehicleRun& log, const Eigen::Vector4d& parameters,
                         const Eigen::Matrix4d& covariance, const DataSource& source) {
  std::string csv = std::string("# accelcal apply ") + AccelcalVersion() +
                    ": accelerations corrected by a calibration (docs/calibration.md)\n";
  for (const auto& [role, file] : source.files) {
    csv += "# " + role + ": " + file.path + " (sha256 " + file.sha256 + ")\n";
  }
  csv += "# command: " + CommandLine() + "\n";
  csv +=
      "# sigma: the calibration's uncertainty of each value, shared by all samples (not the "
      "sensor noise)\n";
  csv += "t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy\n";
  for (int j = 0; j < log.size(); ++j) {
    const CorrectedSample sample =
        CorrectBaseline(parameters, covariance, log.measured_x[j], log.measured_y[j]);
    const double sigma_x = std::sqrt(sample.covariance(0, 0));
    const double sigma_y = std::sqrt(sample.covariance(1, 1));
    const double correlation =
        sigma_x > 0.0 && sigma_y > 0.0 ? sample.covariance(0, 1) / (sigma_x * sigma_y) : 0.0;
    csv += RoundTripDouble(log.timestamp_s[j]) + "," + RoundTripDouble(sample.acceleration.x()) +
           "," + RoundTripDouble(sample.acceleration.y()) + "," + StringPrintf("%.6g", sigma_x) +
           "," + StringPrintf("%.6g", sigma_y) + "," + StringPrintf("%.6g", correlation) + "\n";
  }
  return csv;
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
