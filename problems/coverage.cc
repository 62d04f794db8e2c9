// coverage: is the uncertainty the linear baseline reports right? Simulates K experiments
// of a scenario, fits each, dead-reckons each run, and compares the spread of the
// estimates with the reported covariance: coverage of 68/95/99% intervals and ellipses,
// bias in reported sigmas, chi-square per axis. Then hides one effect of the catalogue
// at a time in the data (left out of the model) and shows what it does to the baseline.
//
//   build/bin/coverage --trials=1000 --effect_trials=200 --json=coverage.json

#include <gflags/gflags.h>

#include <iostream>

#include "io/atomic_file.h"
#include "io/json_file.h"
#include "io/scenario_json.h"
#include "problem_support.h"
#include "reporting/coverage_report.h"
#include "studies/coverage_study.h"

DEFINE_string(scenario, "", "Scenario JSON; empty: the embedded tp2-2018 scenario.");
DEFINE_string(set, "", "Overrides of the scenario, name=value,... (as simulate --set).");
DEFINE_int32(trials, 1000, "Monte Carlo trials of the baseline study (>= 10).");
DEFINE_int32(effect_trials, 200, "Trials per row of the hidden-effect table (0: no table).");
DEFINE_uint64(seed, 1, "Seed; trial i uses the noise streams of (seed, i).");
ACCELCAL_DEFINE_THREADS_FLAG(0);
DEFINE_string(json, "", "Write the results as JSON to this file (atomically).");
ACCELCAL_DEFINE_PROGRESS_FLAG();
ACCELCAL_FLAG_RANGE(trials, 10, 10000000);
ACCELCAL_FLAG_RANGE(effect_trials, 0, 10000000);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Checks the linear baseline's reported covariance by Monte Carlo on a scenario, and shows\n"
    "what each effect of the catalogue does when it is in the data but not in the model.\n"
    "Biases are in reported standard deviations; coverages in percent.\n"
    "Exit status: 0 on success, 2 on bad input (one line on stderr; nothing is written).\n\n"
    "  coverage [--scenario=FILE] [--trials=1000] [--effect_trials=200] [--json=coverage.json]\n"
    "           [--progress=auto|always|never]";

int Run(int argc, char** argv) {
  if (!InitProblem("coverage", kUsage, "problems/coverage", &argc, &argv)) return kExitBadInput;
  Status status;
  if (FLAGS_effect_trials != 0 && FLAGS_effect_trials < 10) {
    status = Status::Error("--effect_trials must be 0 or at least 10");
  }
  ProgressStyle progress_style;
  if (status.ok()) status = ProgressStyleFromFlag(FLAGS_progress, &progress_style);
  Scenario scenario;
  DataSource source;
  if (status.ok()) {
    status = LoadSimulationScenario(FLAGS_scenario, FLAGS_set, FLAGS_seed, {{"--json", FLAGS_json}},
                                    &scenario, &source);
  }
  if (!status.ok()) return ExitWithError("coverage", status);

  CoverageOptions options;
  options.trials = FLAGS_trials;
  options.seed = FLAGS_seed;
  options.threads = FLAGS_threads;
  CoverageReport report;
  report.scenario_name = scenario.name;
  report.seed = FLAGS_seed;
  // One count and one time left over the baseline study and the table together.
  const int64_t table_trials = static_cast<int64_t>(EffectImpactRows()) * FLAGS_effect_trials;
  ProgressPrinter progress("coverage", "trials", progress_style, &std::cerr);
  options.progress = ProgressPart(progress.Callback(), 0, FLAGS_trials + table_trials);
  report.baseline = RunCoverageStudy(scenario, options);
  if (FLAGS_effect_trials > 0) {
    options.trials = FLAGS_effect_trials;
    options.progress = ProgressPart(progress.Callback(), FLAGS_trials, FLAGS_trials + table_trials);
    report.effects = RunEffectImpactTable(scenario, options);
  }
  std::string json_text;
  if (!FLAGS_json.empty())
    status = JsonText(WithProvenance(CoverageReportJson(report), source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("coverage", status);
  std::cout << WithDataLine(source, CoverageText(report)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("coverage", accelcal::Run, argc, argv);
}
