// min_samples: the fewest tilt-test samples that still decide which landmark the vehicle
// reached, for several test designs (the reference report's last question).
//
// The endpoint's covariance is J sigma^2 (A^T A)^-1 J^T (shrinks with N) + the run's own
// noise part (does not); P(wrong landmark) is the Gaussian mass outside the true
// landmark's Mahalanobis decision cell. N_min is the smallest N with P(wrong) <= --max_error;
// N_min_3sigma the smallest whose 3-sigma ellipse holds one landmark. Both are checked
// by Monte Carlo: subsets of the real test, and full simulation of test and run.
//
//   build/bin/min_samples --data_dir=../shared/data/tp2-2018 --design=all --json=min_samples.json

#include "studies/min_samples.h"

#include <gflags/gflags.h>

#include <algorithm>
#include <iostream>

#include "io/json_file.h"
#include "io/scenario_json.h"
#include "problem_support.h"
#include "reporting/min_samples_report.h"

DEFINE_string(data_dir, "",
              // clang-format off
              "Folder with the course layout or the CSV layout. Empty (and no --*_file): simulate the embedded tp2-2018 scenario.");
// clang-format on
ACCELCAL_DEFINE_DATA_FILE_FLAGS();
DEFINE_string(
    design, "all",
    // clang-format off
              "The tilt-test design whose N samples are judged: uniform (N samples evenly over one turn, 0 to 360 deg, like the course's sweep), four (N/4 static samples at each of 0, 90, 180 and 270 deg), two (N/2 at each of 45 and 225 deg), optimal (N/2 at each of the two positions, on a 5 deg grid, that give the smallest P(wrong landmark) at the uniform design's N_min, or at 100 samples when uniform is not run), or all. docs/min_samples.md explains the question, the criterion and the Monte Carlo check.");
// clang-format on
DEFINE_double(max_error, 0.01,
              // clang-format off
    "The criterion: the largest acceptable probability of deciding a wrong landmark, 1e-6 to 0.499.");
// clang-format on
DEFINE_double(g, 9.8, "Gravity in m/s^2.");
DEFINE_int32(repetitions, 1000, "Monte Carlo repetitions per checked N (0: no Monte Carlo).");
DEFINE_uint64(seed, 1, "Seed of the Monte Carlo.");
ACCELCAL_DEFINE_THETA_UNIT_FLAG();
ACCELCAL_DEFINE_THREADS_FLAG(0);
DEFINE_string(json, "",
              "Write the designs, their curves and N_min as JSON to this file (atomically).");
ACCELCAL_DEFINE_PROGRESS_FLAG();
ACCELCAL_FLAG_RANGE(max_error, 1e-6, 0.499);
ACCELCAL_FLAG_RANGE(g, 1.0, 100.0);
ACCELCAL_FLAG_RANGE(repetitions, 0, 1000000);

namespace accelcal {
namespace {

// clang-format off
constexpr char kUsage[] =
    "Finds the fewest tilt-test samples N that still decide the landmark, per test design, from the\n"
    "endpoint covariance as a function of N (parameters) plus the run's own noise (fixed), and checks\n"
    "the analytic error probability by Monte Carlo. Positions in m, angles in rad.\n"
    "The Monte Carlo takes a minute or more; --progress shows how far it has got.\n"
    "Exit status: 0 on success, 2 on bad input.\n\n"
    "  min_samples --data_dir=../shared/data/tp2-2018 [--design=all] [--max_error=0.01] [--progress=always]";
// clang-format on

struct Inputs : Experiment {
  Scenario scenario;  // for the full-simulation check
};

Status Load(Inputs* inputs) {
  ACCELCAL_RETURN_IF_ERROR(LoadDefaultScenario(&inputs->scenario));
  LoadOptions options;
  ACCELCAL_RETURN_IF_ERROR(LoadOptionsFromFlags(FLAGS_theta_unit, &options));
  return LoadExperiment(ACCELCAL_DATA_FLAGS(), "", FLAGS_seed, {}, options,
                        {{"--json", FLAGS_json}}, inputs);
}

Status DesignsFromFlag(std::vector<std::string>* designs) {
  const std::vector<std::string>& names = DesignNames();
  if (FLAGS_design == "all") {
    *designs = names;
  } else if (std::find(names.begin(), names.end(), FLAGS_design) != names.end()) {
    *designs = {FLAGS_design};
  } else {
    return Status::Error("--design must be uniform, four, two, optimal or all, got '" +
                         FLAGS_design + "'");
  }
  return Status::Ok();
}

MinSamplesOptions OptionsFromFlags(const Inputs& inputs, std::vector<std::string> designs,
                                   ProgressFn progress) {
  MinSamplesOptions options;
  options.designs = std::move(designs);
  options.max_error = FLAGS_max_error;
  options.gravity_mps2 = ChooseGravity(inputs.conditions, FLAGS_g);
  options.repetitions = FLAGS_repetitions;
  options.seed = FLAGS_seed;
  options.threads = FLAGS_threads;
  // A simulated test has the full simulation.
  options.subset_checks = !ACCELCAL_DATA_FLAGS().MeasuredDataFlag().empty();
  options.progress = std::move(progress);
  return options;
}

int Run(int argc, char** argv) {
  if (!InitProblem("min_samples", kUsage, "problems/min_samples", &argc, &argv))
    return kExitBadInput;
  std::vector<std::string> designs;
  Inputs inputs;
  MinSamplesReport report;
  std::string json_text;
  ProgressStyle progress_style;
  Status status = DesignsFromFlag(&designs);
  if (status.ok()) status = ProgressStyleFromFlag(FLAGS_progress, &progress_style);
  if (status.ok()) status = Load(&inputs);
  ProgressPrinter progress("min_samples", "Monte Carlo trials", progress_style, &std::cerr);
  if (status.ok()) {
    status = RunMinSamplesStudy(
        inputs.test, inputs.run, inputs.conditions, inputs.landmarks, inputs.scenario,
        OptionsFromFlags(inputs, designs, progress.Callback()), &report.study);
  }
  report.landmarks = inputs.landmarks;
  report.max_error = FLAGS_max_error;
  if (status.ok() && !FLAGS_json.empty())
    status = JsonText(WithProvenance(MinSamplesJson(report), inputs.data_source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("min_samples", status);
  std::cout << WithDataLine(inputs.data_source, MinSamplesText(report)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("min_samples", accelcal::Run, argc, argv);
}
