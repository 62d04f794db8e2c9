// trajectory: dead reckoning of the vehicle run with the baseline's corrections, the
// endpoint's covariance (estimated parameters and the run's own noise), and which
// landmark the vehicle reached.
//
// The corrected acceleration a_j = (m_j - b)/(1 + s) is integrated twice by the
// trapezoidal rule from p0, v0, so p_end = p0 + v0 T + sum_j w_j a_j and
//   Cov(p_end) = J Sigma_params J^T + sum_j w_j^2 sigma^2 / (1 + s)^2   (per axis).
// Each landmark is scored by its Mahalanobis distance; the most probable one is
// reported as reached only if its chi-square(2) p-value is at least --landmark_alpha.
//
// Inputs: a data directory (course layout or CSV layout) or single files. Outputs: a
// table on stdout, JSON (--json) and the path with its covariance as CSV (--path_csv),
// which tools/plot_trajectory.py draws.
//
//   build/bin/trajectory --data_dir=../shared/data/tp2-2018 --json=t.json --path_csv=path.csv

#include "estimation/tilt_table/trajectory.h"

#include <gflags/gflags.h>

#include <cmath>
#include <iostream>

#include "estimation/tilt_table/error_budget.h"
#include "estimation/tilt_table/landmark_decision.h"
#include "estimation/tilt_table/linear_ls.h"
#include "io/atomic_file.h"
#include "io/calibration_file.h"
#include "io/course_data.h"
#include "io/json_file.h"
#include "problem_support.h"
#include "reporting/trajectory_report.h"

// clang-format off
DEFINE_string(data_dir, "", "Folder with the course layout (ensayo.mat, acel.mat, puntos.mat, datos.txt) or the CSV layout (calibration.csv, trajectory.csv, landmarks.csv, scenario.json).");
ACCELCAL_DEFINE_DATA_FILE_FLAGS();
DEFINE_string(calibration, "", "A calibration file (calibrate --calibration_out, docs/calibration.md) in place of the tilt test: its bias, scale and covariance correct the run; the folder's tilt test is not read.");
ACCELCAL_DEFINE_THETA_UNIT_FLAG();
DEFINE_double(g, 9.8, "Gravity in m/s^2 used to fit the tilt test, 1 to 100.");
DEFINE_double(landmark_alpha, 0.01, "Significance level of the landmark decision, in (0, 1): the most probable landmark counts as reached only if its chi-square(2) p-value is at least this.");
// clang-format on
DEFINE_string(json, "", "Write the results as JSON to this file (atomically).");
DEFINE_string(path_csv, "",
              "Write the corrected and raw path with its covariance (m, m^2) as CSV to this file.");
DEFINE_int32(path_stride, 10,
             "Keep every Nth run sample in --path_csv (>= 1; the last is always kept).");
ACCELCAL_FLAG_RANGE(g, 1.0, 100.0);
ACCELCAL_FLAG_OPEN_RANGE(landmark_alpha, 0.0, 1.0);
ACCELCAL_RENAMED_FLAG(alpha, landmark_alpha);
ACCELCAL_FLAG_RANGE(path_stride, 1, 1e9);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Dead-reckons the vehicle run corrected by the baseline fit (bias in m/s^2, scale\n"
    "dimensionless), gives the endpoint (m) with its covariance (m^2) split into the\n"
    "parameters' part and the run's own noise part, and decides which landmark the vehicle\n"
    "reached. Times are in seconds, positions in metres, accelerations in m/s^2.\n"
    "Exit status: 0 on success, 2 on bad input (one line on stderr; nothing is written).\n\n"
    "  trajectory --data_dir=../shared/data/tp2-2018 [--json=t.json] [--path_csv=path.csv]";

Status ValidateFlags() {
  if (!FLAGS_calibration.empty() && !FLAGS_calibration_file.empty()) {
    return Status::Error(
        "--calibration and --calibration_file both give the calibration; drop one of the two");
  }
  const bool has_calibration = !FLAGS_calibration.empty() || !FLAGS_calibration_file.empty();
  if (FLAGS_data_dir.empty() && (!has_calibration || FLAGS_run_file.empty() ||
                                 FLAGS_landmarks_file.empty() || FLAGS_conditions_file.empty())) {
    // clang-format off
    return Status::Error(
        "give --data_dir, or all of --calibration_file (or --calibration), --run_file, --landmarks_file and --conditions_file");
    // clang-format on
  }
  return Status::Ok();
}

using Inputs = CourseData;

Status Load(Inputs* inputs, TrajectoryReport* report, DataSource* source) {
  const DataFiles overrides = ACCELCAL_DATA_FLAGS().overrides;
  DataFiles files;
  ACCELCAL_RETURN_IF_ERROR(ResolveDataFiles(FLAGS_data_dir, overrides, &files));
  if (!FLAGS_calibration.empty()) files.calibration.clear();
  ACCELCAL_RETURN_IF_ERROR(CheckOutputPaths(
      {{"--json", FLAGS_json}, {"--path_csv", FLAGS_path_csv}}, InputsOf(FLAGS_data_dir, files)));
  LoadOptions load_options;
  ACCELCAL_RETURN_IF_ERROR(LoadOptionsFromFlags(FLAGS_theta_unit, &load_options));
  ACCELCAL_RETURN_IF_ERROR(LoadDataFiles(files, inputs, load_options));
  PrintInputNotes(inputs->notes);
  report->input_files = FileRoles(files);
  if (!FLAGS_calibration.empty()) report->input_files["calibration"] = FLAGS_calibration;
  return DescribeMeasuredData(FLAGS_data_dir, report->input_files, source);
}

// The baseline from a calibration file: its parameters, covariance and fit.
Status ReadCalibration(BaselineFit* fit) {
  CalibrationRecord record;
  ACCELCAL_RETURN_IF_ERROR(ReadCalibrationFile(FLAGS_calibration, &record));
  ACCELCAL_RETURN_IF_ERROR(
      TwoAxisBaseline(record, FLAGS_calibration, &fit->parameters, &fit->covariance));
  fit->sample_count = record.fit.value("samples", 0);
  return Status::Ok();
}

Status Solve(const Inputs& inputs, TrajectoryReport* report) {
  if (!FLAGS_calibration.empty()) {
    ACCELCAL_RETURN_IF_ERROR(ReadCalibration(&report->fit));
  } else {
    const LinearLsOptions options =
        LinearLsOptionsFor(inputs.conditions, ChooseGravity(inputs.conditions, FLAGS_g));
    ACCELCAL_RETURN_IF_ERROR(EstimateLinearLs(inputs.test, options, &report->fit)
                                 .WithContext(report->input_files["calibration"]));
  }
  TrajectoryOptions trajectory_options;
  trajectory_options.path_stride = FLAGS_path_stride;
  ACCELCAL_RETURN_IF_ERROR(DeadReckon(inputs.run, inputs.conditions, report->fit,
                                      trajectory_options, &report->trajectory)
                               .WithContext(report->input_files["run"]));
  report->conditions = inputs.conditions;
  report->decision = DecideLandmark(report->trajectory.endpoint, report->trajectory.covariance,
                                    inputs.landmarks, FLAGS_landmark_alpha);
  report->budget =
      ComputeErrorBudget(report->trajectory, report->fit, inputs.run, inputs.conditions);
  return Status::Ok();
}

Status Write(const TrajectoryReport& report, const DataSource& source) {
  std::string json_text;
  if (!FLAGS_json.empty())
    ACCELCAL_RETURN_IF_ERROR(JsonText(WithProvenance(TrajectoryJson(report), source), &json_text));
  return WriteOutputFiles(
      {{FLAGS_json, json_text},
       {FLAGS_path_csv, FLAGS_path_csv.empty() ? "" : TrajectoryPathCsv(report.trajectory)}});
}

int Run(int argc, char** argv) {
  if (!InitProblem("trajectory", kUsage, "problems/trajectory", &argc, &argv)) return kExitBadInput;
  Status status = ValidateFlags();
  Inputs inputs;
  TrajectoryReport report;
  DataSource source;
  if (status.ok()) status = Load(&inputs, &report, &source);
  if (status.ok()) status = Solve(inputs, &report);
  if (status.ok()) status = Write(report, source);
  if (!status.ok()) return ExitWithError("trajectory", status);
  std::cout << WithDataLine(source, TrajectoryTable(report)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("trajectory", accelcal::Run, argc, argv);
}
