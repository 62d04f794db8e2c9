// simulate: a tilt-table test and a vehicle run synthesised from a scenario, written in
// the course layout (.mat through libmatio, readable by MATLAB/Octave and by accelcal's
// own loader) or the CSV layout, with truth.json holding every true parameter, the true
// endpoint and the reached landmark.
//
// The sensor model is the spec's (../shared/spec/error-model.md), evaluated by the same
// functions the estimators use; any effect of the catalogue can be set in the scenario
// or on the command line. The output is a function of (scenario, seed) only.
//
//   build/bin/simulate --scenario=data/scenarios/tp2-2018.json --seed=7 --out_dir=sim \
//       --set=angle_offset=0.004,bias_drift_x=0.1

#include <gflags/gflags.h>

#include <cmath>
#include <iostream>

#include "common/format.h"
#include "io/atomic_file.h"
#include "io/course_data.h"
#include "io/json_file.h"
#include "io/scenario_json.h"
#include "problem_support.h"
#include "simulation/scenario.h"

// clang-format off
DEFINE_string(scenario, "", "Scenario JSON (see data/scenarios/tp2-2018.json). Empty: the embedded tp2-2018 scenario, the course's setting.");
DEFINE_uint64(seed, 1, "Seed of the noise; the same seed gives the same files on any machine.");
DEFINE_string(out_dir, "", "Folder to write (created; replaced only with --overwrite).");
DEFINE_string(format, "mat", "mat: ensayo.mat, acel.mat, puntos.mat, datos.txt (the course layout); csv: calibration.csv, trajectory.csv, landmarks.csv, scenario.json.");
// clang-format on
namespace {
// The help text of --set, from the catalogue (gflags keeps the pointer).
const char* SetHelp() {
  // clang-format off
  static const std::string help =
      "Overrides, name=value,...: any parameter of the spec in its unit (" +
      accelcal::CatalogueParametersText() +
      ", ...) or a setting (gravity m/s^2, noise_variance_x_stated (m/s^2)^2, tilt_samples, run_duration s, run_dt s).";
  // clang-format on
  return help.c_str();
}
}  // namespace
DEFINE_string(set, "", SetHelp());
DEFINE_bool(overwrite, false, "Replace --out_dir if it exists and is not empty.");

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Simulates the tilt-table test and the vehicle run of a scenario with every effect of the\n"
    "spec's catalogue, and writes them in the course layout or the CSV layout with truth.json.\n"
    "Angles in rad, times in s, accelerations in m/s^2, positions in m.\n"
    "Exit status: 0 on success, 2 on bad input (one line on stderr; nothing is written).\n\n"
    // clang-format off
    "  simulate --out_dir=sim [--scenario=FILE] [--seed=S] [--format=mat|csv] [--set=name=value,...]";
// clang-format on

Status ValidateFlags() {
  if (FLAGS_out_dir.empty()) return Status::Error("--out_dir is required");
  if (FLAGS_format != "mat" && FLAGS_format != "csv") {
    return Status::Error("--format must be mat or csv, got '" + FLAGS_format + "'");
  }
  return Status::Ok();
}

Status Load(Scenario* scenario, DataSource* source) {
  return LoadSimulationScenario(FLAGS_scenario, FLAGS_set, FLAGS_seed,
                                {{"--out_dir", FLAGS_out_dir, OutputPath::Kind::kFolder}}, scenario,
                                source);
}

Status Write(const Scenario& scenario, const SimulatedData& data, const DataSource& source,
             std::vector<std::string>* written) {
  const DataLayout layout = FLAGS_format == "csv" ? DataLayout::kCsv : DataLayout::kCourseMat;
  return WriteDirectoryAtomically(FLAGS_out_dir, FLAGS_overwrite, [&](const std::string& dir) {
    ACCELCAL_RETURN_IF_ERROR(WriteDataDirectory(dir, layout, data.test, data.run, data.landmarks,
                                                data.conditions, written));
    return WriteJsonAtomically(dir + "/truth.json",
                               WithProvenance(TruthJson(scenario, data, FLAGS_seed), source));
  });
}

std::string Summary(const Scenario& scenario, const SimulatedData& data) {
  std::string text = StringPrintf(
      "accelcal simulate: scenario %s, seed %llu -> %s (%s layout)\n", scenario.name.c_str(),
      static_cast<unsigned long long>(FLAGS_seed), FLAGS_out_dir.c_str(), FLAGS_format.c_str());
  text += StringPrintf("  tilt test    %d samples, theta %.3f to %.3f rad\n", data.test.size(),
                       data.test.theta_rad.front(), data.test.theta_rad.back());
  text += StringPrintf("  vehicle run  %d samples, dt %g s\n", data.run.size(), scenario.run.dt_s);
  text += "  truth       ";
  for (const ParameterInfo& info : ParameterCatalogue()) {
    const double value = scenario.truth.parameters[info.parameter];
    if (value != info.neutral) text += StringPrintf(" %s=%g", info.name, value);
  }
  text += StringPrintf("\n  endpoint     true (%.3f, %.3f) m; nearest landmark %s at %.3g m\n",
                       data.true_endpoint.x(), data.true_endpoint.y(),
                       data.reached_landmark.c_str(), data.reached_distance_m);
  return text;
}

int Run(int argc, char** argv) {
  if (!InitProblem("simulate", kUsage, "problems/simulate", &argc, &argv)) return kExitBadInput;
  Status status = ValidateFlags();
  Scenario scenario;
  DataSource source;
  if (status.ok()) status = Load(&scenario, &source);
  if (!status.ok()) return ExitWithError("simulate", status);
  const SimulatedData data = SimulateScenario(scenario, FLAGS_seed);
  std::vector<std::string> written;
  status = Write(scenario, data, source, &written);
  if (!status.ok()) return ExitWithError("simulate", status);
  std::cout << WithDataLine(source, Summary(scenario, data)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("simulate", accelcal::Run, argc, argv);
}
