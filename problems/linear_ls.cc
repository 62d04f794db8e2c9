// linear_ls: per-axis bias and scale factor of two accelerometers from a tilt-table test,
// by linear least squares, solved two ways (closed form and Ceres) as the baseline.
//
// The table is rotated through known angles theta_i in gravity; axis k outputs
//   m_k,i = (1 + s_k) f_k(theta_i) + b_k + zeta_k,i,   fx = -g sin(theta), fy = -g cos(theta),
// with white noise of stated variance sigma_k^2. So y = m - f = b + s f + noise is linear in
// (b, s), estimated per axis with covariance sigma_k^2 (A^T A)^-1.
//
// Inputs: a data directory in the course layout (ensayo.mat + datos.txt) or the CSV layout
// (calibration.csv + scenario.json), or single files; without any, a synthetic test with
// the course's setting simulated (data/scenarios/tp2-2018.json, Table 1 as truth). Outputs: a table
// on stdout, JSON with --json.
//
// The closed form needs only sufficient statistics, so a CSV test is streamed through them
// (io/calibration_stream.h) in bounded memory whatever its length; the samples are kept only
// for the Ceres cross-check, which holds them all with their residuals (about 1 KB per
// sample) and is skipped, saying so, above --ceres_max_samples.
//
//   build/bin/linear_ls --data_dir=../shared/data/tp2-2018 --json=linear_ls.json

#include "estimation/tilt_table/linear_ls.h"

#include <gflags/gflags.h>

#include <iostream>
#include <limits>
#include <optional>

#include "estimation/tilt_table/ceres_linear_ls.h"
#include "io/calibration_stream.h"
#include "io/course_data.h"
#include "io/json_file.h"
#include "io/run_conditions.h"
#include "io/scenario_json.h"
#include "problem_support.h"
#include "reporting/linear_ls_report.h"
#include "simulation/scenario.h"

// clang-format off
DEFINE_string(data_dir, "", "Folder with the course layout (ensayo.mat, datos.txt, ...) or the CSV layout (calibration.csv, scenario.json, ...). Empty: simulate the embedded default.");
ACCELCAL_DEFINE_CALIBRATION_FILE_FLAG();
ACCELCAL_DEFINE_CONDITIONS_FILE_FLAG();
DEFINE_double(g, 9.8, "Gravity in m/s^2 (the course takes 9.8). Only (1 + scale) * g is observable, so an error here moves scale_x and scale_y. A 'gravity' in scenario.json is used unless this flag is given.");
DEFINE_string(json, "", "Write the results as JSON to this file (written atomically).");
DEFINE_string(scenario, "", "Without data: the scenario to simulate (JSON, see data/scenarios/); empty: the embedded tp2-2018 scenario, the course's setting with Table 1 as truth.");
DEFINE_string(set, "", "Without data: overrides of the scenario, name=value,... (as simulate --set), e.g. --set=angle_offset=0.004 to see what an unmodelled effect does.");
DEFINE_uint64(seed, 1, "Without data: the seed of the simulated test.");
ACCELCAL_DEFINE_THETA_UNIT_FLAG();
// Threads serve Ceres and the closed form's pass over a test held in memory (which splits only
// tests of at least 2^18 samples per thread).
ACCELCAL_DEFINE_THREADS_FLAG(1);
DEFINE_int64(ceres_max_samples, 1000000, "The Ceres cross-check runs on tests of at most this many samples; it holds every sample and its residuals in memory (about 1 GB and 8 s at 10^6 samples). A larger test is solved in closed form only, which streams a CSV file in bounded memory whatever its size, and the output says that Ceres was skipped. 0: never run Ceres.");
// clang-format on

ACCELCAL_FLAG_RANGE(g, 1.0, 100.0);
ACCELCAL_FLAG_RANGE(ceres_max_samples, 0, 1e12);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Estimates bias_x, scale_x, bias_y, scale_y (bias in m/s^2, scale dimensionless) from a\n"
    "tilt-table test by linear least squares, closed form and Ceres, with covariance and\n"
    "chi-square against the stated noise variances ((m/s^2)^2). Angles are in radians.\n"
    "Exit status: 0 on success, 2 on bad input (one line on stderr; nothing is written).\n\n"
    "  linear_ls --data_dir=../shared/data/tp2-2018 [--json=out.json] [--g=9.8]\n"
    "  linear_ls [--set=angle_offset=0.004]   # simulated tp2-2018 scenario, Table 1 as truth";

Status ValidateFlags() {
  const bool has_data = !FLAGS_data_dir.empty() || !FLAGS_calibration_file.empty();
  if (has_data && FLAGS_data_dir.empty() &&
      (FLAGS_calibration_file.empty() || FLAGS_conditions_file.empty())) {
    return Status::Error(
        "--calibration_file needs --conditions_file (the stated noise variances) or --data_dir");
  }
  return Status::Ok();
}

// The tilt test as the two solvers need it: the closed form its sufficient statistics, Ceres
// its samples.
struct TiltTest {
  CalibrationTest samples;  // empty beyond --ceres_max_samples when streamed
  // Set when a CSV file was streamed; otherwise the statistics are taken from `samples`.
  std::optional<CalibrationAccumulator> streamed_statistics;
};

// One pass over the file: every batch goes into the statistics, and into `test->samples`
// while they stay within --ceres_max_samples (beyond it they are dropped and freed).
Status StreamCalibration(const std::string& path, AngleUnit theta_unit, double gravity_mps2,
                         TiltTest* test) {
  test->streamed_statistics.emplace(gravity_mps2);
  CalibrationAccumulator& statistics = *test->streamed_statistics;
  CalibrationTest& samples = test->samples;
  CalibrationStreamOptions options;
  options.theta_unit = theta_unit;
  return StreamCalibrationCsv(
      path, options,
      [&](const CalibrationTest& batch) {
        statistics.AddTest(batch);
        if (statistics.x().count() > FLAGS_ceres_max_samples) {
          if (samples.size() > 0) samples = CalibrationTest();
          return;
        }
        samples.Append(batch);
      },
      nullptr);
}

// Load (or simulate) the tilt test and the options it is solved with.
Status LoadInputs(TiltTest* test, LinearLsOptions* options, LinearLsReport* report,
                  DataSource* source) {
  options->gravity_mps2 = FLAGS_g;
  if (FLAGS_data_dir.empty() && FLAGS_calibration_file.empty()) {
    RunInputs scenario_inputs;
    if (!FLAGS_scenario.empty()) scenario_inputs.files.push_back(FLAGS_scenario);
    ACCELCAL_RETURN_IF_ERROR(CheckOutputPaths({{"--json", FLAGS_json}}, scenario_inputs));
    Scenario scenario;
    ACCELCAL_RETURN_IF_ERROR(LoadScenarioOrDefault(FLAGS_scenario, FLAGS_set, &scenario));
    const SimulatedData data = SimulateScenario(scenario, FLAGS_seed);
    ACCELCAL_RETURN_IF_ERROR(DescribeSimulation(scenario, FLAGS_scenario, FLAGS_seed, source));
    test->samples = data.test;
    *options = LinearLsOptionsFor(data.conditions, ChooseGravity(data.conditions, FLAGS_g));
    report->simulation_seed = FLAGS_seed;
    report->scenario_name = scenario.name;
    report->truth = BaselineTruth(scenario.truth.parameters);
    return Status::Ok();
  }
  ACCELCAL_RETURN_IF_ERROR(RefuseSimulationFlags(
      FLAGS_data_dir.empty() ? "--calibration_file" : "--data_dir", {"scenario", "set", "seed"}));
  DataFiles overrides;
  overrides.calibration = FLAGS_calibration_file;
  overrides.conditions = FLAGS_conditions_file;
  DataFiles files;
  ACCELCAL_RETURN_IF_ERROR(ResolveDataFiles(FLAGS_data_dir, overrides, &files));
  ACCELCAL_RETURN_IF_ERROR(
      CheckOutputPaths({{"--json", FLAGS_json}}, InputsOf(FLAGS_data_dir, files)));
  LoadOptions load_options;
  ACCELCAL_RETURN_IF_ERROR(LoadOptionsFromFlags(FLAGS_theta_unit, &load_options));
  // The conditions are read first because streaming needs g, but a fault of the calibration
  // file is still reported before one of the conditions.
  RunConditions conditions;
  const Status conditions_status = LoadRunConditions(files.conditions, &conditions);
  options->gravity_mps2 =
      conditions_status.ok() ? ChooseGravity(conditions, FLAGS_g) : options->gravity_mps2;
  if (IsCsvPath(files.calibration)) {
    ACCELCAL_RETURN_IF_ERROR(
        StreamCalibration(files.calibration, load_options.theta_unit, options->gravity_mps2, test));
  } else {
    std::vector<std::string> notes;
    ACCELCAL_RETURN_IF_ERROR(
        LoadCalibrationTest(files.calibration, &test->samples, load_options, &notes));
    PrintInputNotes(notes);
  }
  ACCELCAL_RETURN_IF_ERROR(conditions_status);
  *options = LinearLsOptionsFor(conditions, options->gravity_mps2);
  report->input_files = {{"calibration", files.calibration}, {"conditions", files.conditions}};
  return DescribeMeasuredData(FLAGS_data_dir, report->input_files, source);
}

// The closed form, then the Ceres cross-check unless the test is too large to hold.
Status Solve(const TiltTest& test, const LinearLsOptions& options, LinearLsReport* report) {
  const std::string calibration_name =
      report->simulation_seed ? "simulated test" : report->input_files["calibration"];
  CalibrationAccumulator statistics(options.gravity_mps2);
  if (test.streamed_statistics) {
    statistics = *test.streamed_statistics;
  } else {
    statistics.AddTest(test.samples, ThreadCount(FLAGS_threads));
  }
  // BaselineFit counts samples in an int.
  if (statistics.x().count() > std::numeric_limits<int>::max()) {
    return Status::Error(calibration_name + ": " + std::to_string(statistics.x().count()) +
                         " samples, more than the 2^31 - 1 this program can count");
  }
  // A degenerate design is a fault of the calibration file: name it.
  ACCELCAL_RETURN_IF_ERROR(
      SolveLinearLs(statistics, options, &report->closed_form).WithContext(calibration_name));
  report->gravity_mps2 = options.gravity_mps2;
  report->noise_variance_x = options.noise_variance_x;
  report->noise_variance_y = options.noise_variance_y;
  report->theta_min_rad = statistics.theta_min_rad();
  report->theta_max_rad = statistics.theta_max_rad();
  report->ceres_skipped =
      CeresSkippedReason(report->closed_form.sample_count, FLAGS_ceres_max_samples);
  if (!report->ceres_skipped.empty()) return Status::Ok();
  CeresLinearLsOptions ceres_options;
  ceres_options.model = options;
  ceres_options.num_threads = ThreadCount(FLAGS_threads);
  return EstimateLinearLsWithCeres(test.samples, ceres_options, &report->ceres);
}

int Run(int argc, char** argv) {
  if (!InitProblem("linear_ls", kUsage, "problems/linear_ls", &argc, &argv)) return kExitBadInput;
  TiltTest test;
  LinearLsOptions options;
  LinearLsReport report;
  DataSource source;
  std::string json_text;
  Status status = ValidateFlags();
  if (status.ok()) status = LoadInputs(&test, &options, &report, &source);
  if (status.ok()) status = Solve(test, options, &report);
  if (status.ok() && !FLAGS_json.empty())
    status = JsonText(WithProvenance(LinearLsJson(report), source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("linear_ls", status);
  std::cout << WithDataLine(source, LinearLsTable(report, FLAGS_v >= 1)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("linear_ls", accelcal::Run, argc, argv);
}
