// power: the detection rate of discovery against the size of each hidden effect, in units
// of that effect's own sigma on the scenario. Each cell simulates --trials datasets with
// one effect hidden and counts how often discover names it.
//
//   build/bin/power --trials=40 --sizes=2,3,4,6 --json=power.json

#include <gflags/gflags.h>

#include <iostream>
#include <sstream>

#include "common/format.h"
#include "io/atomic_file.h"
#include "io/csv_reader.h"
#include "io/json_file.h"
#include "io/scenario_json.h"
#include "problem_support.h"
#include "studies/power_study.h"

DEFINE_string(scenario, "", "Scenario JSON; empty: the embedded tp2-2018 scenario.");
DEFINE_string(set, "", "Overrides of the scenario, name=value,... (as simulate --set).");
DEFINE_string(sizes, "2,3,4,6",
              "Effect sizes in units of each effect's sigma, comma-separated (> 0).");
DEFINE_int32(trials, 40, "Datasets per cell (>= 10).");
DEFINE_double(alpha, 0.01, "Discovery's family-wise error rate, in (0, 0.5).");
DEFINE_uint64(seed, 1, "Seed.");
DEFINE_int32(threads, 0, "Threads (0: all cores).");
DEFINE_string(json, "", "Write the table as JSON to this file (atomically).");
ACCELCAL_FLAG_RANGE(trials, 10, 10000000);
ACCELCAL_FLAG_OPEN_RANGE(alpha, 0.0, 0.5);
ACCELCAL_FLAG_RANGE(threads, 0, 256);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Measures how often discovery names an effect hidden at a given size (in sigmas of that "
    "effect).\n"
    "Exit status: 0 on success, 2 on bad input.\n\n"
    "  power [--trials=40] [--sizes=2,3,4,6] [--json=power.json]";

int Run(int argc, char** argv) {
  if (!InitProblem("power", kUsage, "problems/power", &argc, &argv)) return kExitBadInput;
  PowerOptions options;
  options.sizes_sigma.clear();
  std::istringstream stream(FLAGS_sizes);
  Status status;
  for (std::string item; std::getline(stream, item, ',');) {
    double size;
    if (!ParseFiniteNumber(item, &size) || !(size > 0.0) || size > 1000.0)
      status = Status::Error("--sizes: '" + item.substr(0, 40) +
                             "' is not a number of sigmas in (0, 1000]");
    options.sizes_sigma.push_back(size);
  }
  if (status.ok() && options.sizes_sigma.empty()) status = Status::Error("--sizes is empty");
  if (status.ok() && options.sizes_sigma.size() > 50)
    status = Status::Error("--sizes lists more than 50 sizes");
  Scenario scenario;
  RunInputs inputs;
  if (!FLAGS_scenario.empty()) inputs.files.push_back(FLAGS_scenario);
  if (status.ok()) status = CheckOutputPaths({{"--json", FLAGS_json}}, inputs);
  if (status.ok()) status = LoadScenarioOrDefault(FLAGS_scenario, FLAGS_set, &scenario);
  if (!status.ok()) return ExitWithError("power", status);
  options.trials = FLAGS_trials;
  options.alpha = FLAGS_alpha;
  options.seed = FLAGS_seed;
  options.threads = FLAGS_threads;
  const std::vector<PowerRow> table = RunPowerStudy(scenario, options);

  std::string text = StringPrintf(
      "accelcal power: how often discover names an effect hidden at k sigma (scenario %s, %d "
      "datasets per cell, "
      "alpha %g)\n\n  effect                 sigma (unit)              ",
      scenario.name.c_str(), options.trials, options.alpha);
  for (double size : options.sizes_sigma) text += StringPrintf("  %4.1f sigma", size);
  text += "\n";
  nlohmann::json rows = nlohmann::json::array();
  for (const PowerRow& row : table) {
    const ParameterInfo& info = Info(row.effect);
    text += StringPrintf("  %-22s %.2e %-13s", info.name, row.sigma, info.unit);
    for (double rate : row.detection) text += StringPrintf("  %9.0f%%", 100 * rate);
    text += "\n";
    rows.push_back({{"name", info.name},
                    {"sigma", row.sigma},
                    {"unit", info.unit},
                    {"sizes_sigma", options.sizes_sigma},
                    {"detection", row.detection},
                    {"other_effects_named", row.other_effects}});
  }
  text += StringPrintf(
      "  (Monte Carlo sd of a rate p from %d datasets: sqrt(p(1-p)/%d), at most %.0f%%)\n",
      options.trials, options.trials, 50.0 / std::sqrt(options.trials));
  std::string json_text;
  if (!FLAGS_json.empty()) {
    status = JsonText(nlohmann::json({{"problem", "power"}, {"rows", rows}}), &json_text);
  }
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("power", status);
  std::cout << text << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("power", accelcal::Run, argc, argv);
}
