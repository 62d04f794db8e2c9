// power: the detection rate of discovery against the size of each hidden effect, in units
// of that effect's own sigma on the scenario. Each cell simulates --trials datasets with
// one effect hidden and counts how often discover names it.
//
//   build/bin/power --trials=40 --sizes=2,3,4,6 --json=power.json

#include <gflags/gflags.h>

#include <iostream>
#include <sstream>

#include "io/csv_reader.h"
#include "io/json_file.h"
#include "io/scenario_json.h"
#include "problem_support.h"
#include "reporting/power_report.h"
#include "studies/power_study.h"

DEFINE_string(scenario, "", "Scenario JSON; empty: the embedded tp2-2018 scenario.");
DEFINE_string(set, "", "Overrides of the scenario, name=value,... (as simulate --set).");
DEFINE_string(sizes, "2,3,4,6",
              "Effect sizes in units of each effect's sigma, comma-separated (> 0).");
DEFINE_int32(trials, 40, "Datasets per cell (>= 10).");
DEFINE_double(alpha, 0.01, "Discovery's family-wise error rate, in (0, 0.5).");
DEFINE_uint64(seed, 1, "Seed.");
ACCELCAL_DEFINE_THREADS_FLAG(0);
DEFINE_string(json, "", "Write the table as JSON to this file (atomically).");
ACCELCAL_DEFINE_PROGRESS_FLAG();
ACCELCAL_FLAG_RANGE(trials, 10, 10000000);
ACCELCAL_FLAG_OPEN_RANGE(alpha, 0.0, 0.5);

namespace accelcal {
namespace {

// clang-format off
constexpr char kUsage[] =
    "Measures how often discovery names an effect hidden at a given size (in sigmas of that effect).\n"
    // clang-format on
    "Takes minutes (about 7 at the defaults on 2 cores); --progress shows how far it has got.\n"
    "Exit status: 0 on success, 2 on bad input.\n\n"
    "  power [--trials=40] [--sizes=2,3,4,6] [--json=power.json] [--progress=always]";

// --sizes as numbers of sigmas; when several are bad, the message names the last.
Status SizesFromFlag(std::vector<double>* sizes) {
  sizes->clear();
  std::istringstream stream(FLAGS_sizes);
  Status status;
  for (std::string item; std::getline(stream, item, ',');) {
    double size;
    if (!ParseFiniteNumber(item, &size) || !(size > 0.0) || size > 1000.0)
      status = Status::Error("--sizes: '" + item.substr(0, 40) +
                             "' is not a number of sigmas in (0, 1000]");
    sizes->push_back(size);
  }
  if (status.ok() && sizes->empty()) status = Status::Error("--sizes is empty");
  if (status.ok() && sizes->size() > 50) status = Status::Error("--sizes lists more than 50 sizes");
  return status;
}

int Run(int argc, char** argv) {
  if (!InitProblem("power", kUsage, "problems/power", &argc, &argv)) return kExitBadInput;
  PowerReport report;
  PowerOptions& options = report.options;
  Status status = SizesFromFlag(&options.sizes_sigma);
  ProgressStyle progress_style;
  if (status.ok()) status = ProgressStyleFromFlag(FLAGS_progress, &progress_style);
  Scenario scenario;
  DataSource source;
  if (status.ok()) {
    status = LoadSimulationScenario(FLAGS_scenario, FLAGS_set, FLAGS_seed, {{"--json", FLAGS_json}},
                                    &scenario, &source);
  }
  if (!status.ok()) return ExitWithError("power", status);
  options.trials = FLAGS_trials;
  options.alpha = FLAGS_alpha;
  options.seed = FLAGS_seed;
  options.threads = FLAGS_threads;
  report.scenario_name = scenario.name;
  ProgressPrinter progress("power", "trials", progress_style, &std::cerr);
  options.progress = progress.Callback();
  report.rows = RunPowerStudy(scenario, options);
  std::string json_text;
  if (!FLAGS_json.empty()) status = JsonText(WithProvenance(PowerJson(report), source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("power", status);
  std::cout << WithDataLine(source, PowerText(report)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("power", accelcal::Run, argc, argv);
}
