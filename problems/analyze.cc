// analyze: from measured data to a report a person can read. Baseline fit, trajectory and
// landmark decision, discovery (what the baseline gets wrong, the named cause, the gain),
// the joint solution with what discovery selected, and the minimum number of samples,
// in that order; then report.md, a self-contained report.html, results.json and the
// figures, written to a temporary sibling of --out_dir and renamed into place at the end.
//
// Without --data_dir it simulates the course's setting (data/scenarios/tp2-2018.json) with
// one effect hidden in it (--set, default angle_offset=0.004), stated in the report as
// the truth.
//
//   build/bin/analyze --data_dir=../shared/data/tp2-2018 --out_dir=report --overwrite

#include <gflags/gflags.h>

#include <iostream>

#include "estimation/tilt_table/ceres_linear_ls.h"
#include "estimation/tilt_table/error_budget.h"
#include "estimation/tilt_table/linear_ls.h"
#include "io/atomic_file.h"
#include "problem_support.h"
#include "reporting/analyze_report.h"
#include "studies/min_samples.h"

DEFINE_string(data_dir, "",
              // clang-format off
              "Folder with the course layout or the CSV layout. Empty (and no --*_file): simulate the embedded tp2-2018 scenario with --set hidden in it.");
// clang-format on
ACCELCAL_DEFINE_DATA_FILE_FLAGS();
DEFINE_string(set, "angle_offset=0.004",
              // clang-format off
              "Without data: the effects hidden in the simulated data, name=value,... in the spec's units (the report states them as the truth).");
// clang-format on
DEFINE_uint64(seed, 1, "Without data: the seed of the simulation.");
ACCELCAL_DEFINE_THETA_UNIT_FLAG();
DEFINE_string(out_dir, "report", "The report folder to create (replaced only with --overwrite).");
DEFINE_bool(overwrite, false, "Replace --out_dir if it exists and is not empty.");
DEFINE_double(alpha, 0.01,
              // clang-format off
              "Family-wise error rate of discovery's steps (Holm), in (0, 0.5).");
// clang-format on
DEFINE_double(landmark_alpha, 0.01,
              "Significance level of the landmark decision, in (0, 1): the most probable landmark "
              "counts as reached only if its chi-square(2) p-value is at least this.");
DEFINE_double(max_error, 0.01,
              "The minimum-N criterion: the largest acceptable P(wrong landmark), 1e-6 to 0.499.");
DEFINE_double(g, 9.8, "Gravity in m/s^2.");
DEFINE_string(tools_dir, accelcal::DefaultToolsDir(ACCELCAL_TOOLS_DIR),
              // clang-format off
              "Folder of the plot scripts (plot_*.py). Default: PREFIX/share/accelcal/tools for an installed analyze (PREFIX/bin/analyze), else the source tree's tools/.");
// clang-format on
DEFINE_string(python, "/usr/bin/python3", "Python with matplotlib, for the figures.");
ACCELCAL_DEFINE_PROGRESS_FLAG();
ACCELCAL_FLAG_OPEN_RANGE(alpha, 0.0, 0.5);
ACCELCAL_FLAG_OPEN_RANGE(landmark_alpha, 0.0, 1.0);
ACCELCAL_FLAG_RANGE(max_error, 1e-6, 0.499);
ACCELCAL_FLAG_RANGE(g, 1.0, 100.0);

namespace accelcal {
namespace {

// clang-format off
constexpr char kUsage[] =
    "Runs every stage on measured (or simulated) data and writes a report folder: report.md,\n"
    "report.html (figures embedded), results.json and the figures as PNG. Units: m, s, m/s^2, rad.\n"
    "Exit status: 0 on success, 2 on bad input; an interrupted run leaves no partial report.\n"
    "--progress names each of the five steps on stderr as it starts and ends.\n\n"
    "  analyze --data_dir=../shared/data/tp2-2018 --out_dir=report [--overwrite]";
// clang-format on

Status Load(Experiment* inputs) {
  LoadOptions options;
  ACCELCAL_RETURN_IF_ERROR(LoadOptionsFromFlags(FLAGS_theta_unit, &options));
  return LoadExperiment(ACCELCAL_DATA_FLAGS(), FLAGS_set, FLAGS_seed, {"set", "seed"}, options,
                        {{"--out_dir", FLAGS_out_dir, OutputPath::Kind::kFolder}}, inputs);
}

// The steps --progress names; the fifth, the report and its figures, is Run's.
constexpr int kSteps = 5;

Status Analyse(const Experiment& inputs, double gravity, ProgressPrinter* progress,
               AnalyzeReport* r) {
  r->source = inputs.source;
  r->data_source = inputs.data_source;
  r->truth = inputs.truth;
  r->test = inputs.test;
  r->landmarks = inputs.landmarks;
  r->alpha = FLAGS_alpha;
  r->max_error = FLAGS_max_error;
  progress->StartStep(1, kSteps, "baseline fit (closed form and Ceres)");
  const LinearLsOptions linear = LinearLsOptionsFor(inputs.conditions, gravity);
  ACCELCAL_RETURN_IF_ERROR(EstimateLinearLs(inputs.test, linear, &r->linear.closed_form));
  CeresLinearLsOptions ceres;
  ceres.model = linear;
  ACCELCAL_RETURN_IF_ERROR(EstimateLinearLsWithCeres(inputs.test, ceres, &r->linear.ceres));
  r->linear.gravity_mps2 = gravity;
  r->linear.noise_variance_x = linear.noise_variance_x;
  r->linear.noise_variance_y = linear.noise_variance_y;
  r->linear.input_files = inputs.files;
  progress->EndStep();

  progress->StartStep(2, kSteps, "trajectory and landmark decision");
  TrajectoryReport& t = r->trajectory;
  t.fit = r->linear.closed_form;
  t.conditions = inputs.conditions;
  t.input_files = inputs.files;
  ACCELCAL_RETURN_IF_ERROR(
      DeadReckon(inputs.run, inputs.conditions, t.fit, TrajectoryOptions(), &t.trajectory));
  t.decision = DecideLandmark(t.trajectory.endpoint, t.trajectory.covariance, inputs.landmarks,
                              FLAGS_landmark_alpha);
  t.budget = ComputeErrorBudget(t.trajectory, t.fit, inputs.run, inputs.conditions);
  progress->EndStep();

  progress->StartStep(3, kSteps, "discovery and the joint model with what it selected");
  DiscoveryOptions discovery;
  discovery.alpha = FLAGS_alpha;
  discovery.gravity_mps2 = gravity;
  ACCELCAL_RETURN_IF_ERROR(Discover(inputs.test, inputs.run, inputs.conditions, inputs.landmarks,
                                    discovery, &r->discovery));
  progress->EndStep();

  progress->StartStep(4, kSteps, "min_samples: how many calibration samples");
  MinSamplesResult& samples = r->min_samples;
  samples.model =
      EndpointModelOf(t.trajectory, gravity, linear.noise_variance_x, linear.noise_variance_y);
  samples.truth = t.decision.best;
  samples.full_samples = inputs.test.size();
  if (samples.truth >= 0 && inputs.landmarks.size() > 1) {
    samples.designs = AnalyseDesigns(samples.model, inputs.landmarks, samples.truth, DesignNames(),
                                     FLAGS_max_error, samples.full_samples, &samples.uniform_n_min);
  }
  progress->EndStep();
  return Status::Ok();
}

int Run(int argc, char** argv) {
  if (!InitProblem("analyze", kUsage, "problems/analyze", &argc, &argv)) return kExitBadInput;
  Status status;
  if (FLAGS_out_dir.empty()) status = Status::Error("--out_dir must name a folder");
  ProgressStyle progress_style;
  if (status.ok()) status = ProgressStyleFromFlag(FLAGS_progress, &progress_style);
  Experiment inputs;
  if (status.ok()) status = Load(&inputs);
  ProgressPrinter progress("analyze", "steps", progress_style, &std::cerr);
  AnalyzeReport report;
  if (status.ok()) {
    status = Analyse(inputs, ChooseGravity(inputs.conditions, FLAGS_g), &progress, &report);
  }
  FigureOutcome figures;
  if (status.ok()) {
    progress.StartStep(5, kSteps, "report and figures");
    status = WriteDirectoryAtomically(FLAGS_out_dir, FLAGS_overwrite, [&](const std::string& dir) {
      return WriteAnalyzeReport(dir, report, {FLAGS_tools_dir, FLAGS_python}, &figures);
    });
    if (status.ok()) progress.EndStep();
  }
  if (!status.ok()) {
    progress.Close();  // a step that failed left its line open on a terminal
    return ExitWithError("analyze", status);
  }
  std::cout << DataLine(inputs.data_source) << "\n";
  std::cout << "accelcal analyze: " << report.discovery.verdict << "\n  report: " << FLAGS_out_dir
            << "/report.html (and report.md, results.json)\n  figures: "
            << FigureOutcomeLine(figures) << "\n";
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("analyze", accelcal::Run, argc, argv);
}
