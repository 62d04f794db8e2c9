// null_rate: discovery's false-discovery rate on null data. The baseline is the truth
// (Table 1's bias and scale, every other effect neutral, white Gaussian noise of exactly the
// stated variance), so any verdict but "explained" is a false discovery, which
// DiscoveryOptions::alpha promises happens with probability at most alpha. For each tilt-test
// design, noise level and alpha, --datasets null datasets are simulated and discovered; pooled
// over the cells of one alpha, n datasets with a rate p are within the promise when
//
//   p <= alpha + 2 sqrt(alpha (1 - alpha) / n).
//
// Prints one line per cell and the pooled rate per alpha; --json writes the same. The exit
// status is 0 whether or not the rate is within the bound (it is a measurement).
//
//   build/bin/null_rate --datasets=170 --noise_factors=0.25,1,4 --alphas=0.01,0.05 --json=null.json

#include <gflags/gflags.h>

#include <iostream>
#include <sstream>

#include "common/format.h"
#include "io/atomic_file.h"
#include "io/csv_reader.h"
#include "io/json_file.h"
#include "io/scenario_json.h"
#include "problem_support.h"
#include "studies/null_rate_study.h"

DEFINE_string(designs, "course,n2000,eight_positions,half_circle",
              "Tilt-test designs, comma-separated: course (the tp2-2018 scenario's 20001 samples "
              "over [0, 2 pi]), n2000 (2000 uniform over [0, 2 pi)), eight_positions (2000 at 8 "
              "static positions), half_circle (2000 uniform over [0, pi]).");
DEFINE_string(noise_factors, "0.25,1,4",
              "Factors on the stated (and true) noise variances, comma-separated, in (0, 1e4].");
DEFINE_string(alphas, "0.01,0.05",
              "Discovery's alpha values, comma-separated, each in (0, 0.5); the same datasets "
              "serve every alpha.");
DEFINE_int32(datasets, 170,
             "Null datasets per (design, noise factor); the default gives 2040 per alpha over "
             "the 12 default cells.");
DEFINE_uint64(seed, 1, "Seed; dataset i of a cell uses the noise streams of (seed, cell, i).");
DEFINE_int32(threads, 2, "Threads (0: all cores). The counts do not depend on it.");
DEFINE_string(json, "", "Write the table as JSON to this file (atomically).");
ACCELCAL_FLAG_RANGE(datasets, 10, 10000000);
ACCELCAL_FLAG_RANGE(threads, 0, 256);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Measures discovery's false-discovery rate: the fraction of null datasets (bias and scale\n"
    "only, white noise of the stated variance) whose verdict is not \"explained\", per design,\n"
    "noise level and alpha, and pooled per alpha against alpha + 2 Monte Carlo sd.\n"
    "Exit status: 0 on success (also when the rate is above the bound), 2 on bad input.\n\n"
    "  null_rate [--designs=course,n2000] [--noise_factors=0.25,1,4] [--alphas=0.01,0.05]\n"
    "            [--datasets=170] [--threads=2] [--json=null_rate.json]";

// A comma-separated list of numbers, each accepted by `valid` (whose range `range` names).
Status ParseNumbers(const char* flag, const std::string& text, bool (*valid)(double),
                    const char* range, std::vector<double>* values) {
  values->clear();
  std::istringstream stream(text);
  for (std::string item; std::getline(stream, item, ',');) {
    double value;
    if (!ParseFiniteNumber(item, &value) || !valid(value)) {
      return Status::Error(std::string(flag) + ": '" + item.substr(0, 40) +
                           "' is not a number in " + range);
    }
    values->push_back(value);
  }
  if (values->empty()) return Status::Error(std::string(flag) + " is empty");
  if (values->size() > 20) return Status::Error(std::string(flag) + " lists more than 20 values");
  return Status::Ok();
}

Status ParseDesigns(const std::string& text, std::vector<std::string>* designs) {
  designs->clear();
  std::istringstream stream(text);
  for (std::string item; std::getline(stream, item, ',');) {
    if (NullRateDesignDescription(item).empty()) {
      std::string known;
      for (const std::string& name : NullRateDesignNames())
        known += (known.empty() ? "" : ", ") + name;
      return Status::Error("--designs: unknown design '" + item.substr(0, 40) +
                           "' (known: " + known + ")");
    }
    designs->push_back(item);
  }
  if (designs->empty()) return Status::Error("--designs is empty");
  return Status::Ok();
}

template <typename T>
bool HasRepeats(std::vector<T> values) {
  std::sort(values.begin(), values.end());
  return std::adjacent_find(values.begin(), values.end()) != values.end();
}

std::string JoinNumbers(const std::vector<double>& values) {
  std::string text;
  for (const double value : values) text += (text.empty() ? "" : ",") + RoundTripDouble(value);
  return text;
}

std::string JoinNames(const std::vector<std::string>& names, const char* separator = ",") {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : separator) + name;
  return text;
}

// What the design's tilt test is, in numbers.
std::string DescribeTilt(const TiltSchedule& tilt) {
  switch (tilt.kind) {
    case TiltSchedule::Kind::kUniform:
      return StringPrintf("%d samples uniform over [%.6g, %.6g] rad", tilt.sample_count,
                          tilt.theta_begin_rad, tilt.theta_end_rad);
    case TiltSchedule::Kind::kStaticPositions:
      return StringPrintf("%d samples at %zu static positions", tilt.sample_count,
                          tilt.positions_rad.size());
    case TiltSchedule::Kind::kList:
      return StringPrintf("%zu listed angles", tilt.angles_rad.size());
  }
  return "";
}

std::string NameCounts(const std::map<std::string, int>& counts) {
  std::string text;
  for (const auto& [name, count] : counts)
    text += (text.empty() ? "" : ", ") + name + StringPrintf(" %d", count);
  return text.empty() ? "none" : text;
}

void AddCounts(const std::map<std::string, int>& from, std::map<std::string, int>* to) {
  for (const auto& [name, count] : from) (*to)[name] += count;
}

std::string Table(const std::string& header, const NullRateResult& result) {
  std::string text = header;
  text += StringPrintf("\n  %-16s %6s %6s %6s %10s %7s  %7s %6s %7s %9s %6s\n", "design", "noise",
                       "alpha", "n", "not expl.", "rate", "effects", "noise", "checks", "ambiguous",
                       "errors");
  bool any_cell_above = false;
  for (const NullRateCell& cell : result.cells) {
    // The cell alone against its own bound: with many cells, one above is expected by chance.
    const double n = std::max(cell.verdicts, 1);
    const bool above = cell.rate > cell.alpha + 2.0 * std::sqrt(cell.alpha * (1 - cell.alpha) / n);
    any_cell_above = any_cell_above || above;
    text += StringPrintf("  %-16s %6s %6g %6d %10d %6.1f%%%s %7d %6d %7d %9d %6d\n",
                         cell.design.c_str(), ("x" + RoundTripDouble(cell.noise_factor)).c_str(),
                         cell.alpha, cell.verdicts, cell.not_explained, 100.0 * cell.rate,
                         above ? "*" : " ", cell.with_effects, cell.with_noise_findings,
                         cell.with_flagged_checks, cell.cannot_tell_apart, cell.errors);
  }
  text +=
      "  (n: datasets with a verdict; not expl.: verdict other than \"explained\"; then how many\n"
      "   named an effect, a noise finding, a flagged residual check, or could not tell apart)\n";
  if (any_cell_above)
    text += "  (*: above alpha + 2 sd for that cell alone; a few such cells are chance)\n";

  text += "\n  pooled over every design and noise factor, per alpha:\n";
  for (const PooledNullRate& pooled : result.pooled) {
    text += StringPrintf(
        "  alpha %-6g %d/%d = %.2f%% (sd %.2f%%); bound alpha + 2 sqrt(alpha(1-alpha)/n) = %.2f%%: "
        "%s\n",
        pooled.alpha, pooled.not_explained, pooled.verdicts, 100.0 * pooled.rate,
        100.0 * pooled.rate_stddev, 100.0 * pooled.bound,
        pooled.within ? "within" : "ABOVE the bound");
    if (pooled.errors > 0)
      text += StringPrintf("  alpha %-6g %d datasets where discover returned an error\n",
                           pooled.alpha, pooled.errors);
  }
  text += "\n  what the false discoveries claimed, per alpha (datasets):\n";
  for (const PooledNullRate& pooled : result.pooled) {
    std::map<std::string, int> verdicts, effects, noise, checks;
    for (const NullRateCell& cell : result.cells) {
      if (cell.alpha != pooled.alpha) continue;
      AddCounts(cell.verdict_counts, &verdicts);
      AddCounts(cell.effects_named, &effects);
      AddCounts(cell.noise_findings_named, &noise);
      AddCounts(cell.checks_flagged, &checks);
    }
    verdicts.erase("explained");
    text += StringPrintf("  alpha %g: verdicts %s; effects %s; noise %s; checks %s\n", pooled.alpha,
                         NameCounts(verdicts).c_str(), NameCounts(effects).c_str(),
                         NameCounts(noise).c_str(), NameCounts(checks).c_str());
  }
  text += StringPrintf("\n  (%.0f s on %d thread%s)\n", result.seconds, result.threads,
                       result.threads == 1 ? "" : "s");
  return text;
}

nlohmann::json Json(const nlohmann::json& header, const NullRateResult& result) {
  nlohmann::json json = header;
  nlohmann::json cells = nlohmann::json::array();
  for (const NullRateCell& cell : result.cells) {
    cells.push_back({{"design", cell.design},
                     {"noise_factor", cell.noise_factor},
                     {"alpha", cell.alpha},
                     {"datasets", cell.datasets},
                     {"errors", cell.errors},
                     {"verdicts", cell.verdicts},
                     {"not_explained", cell.not_explained},
                     {"rate", cell.rate},
                     {"with_effects", cell.with_effects},
                     {"with_noise_findings", cell.with_noise_findings},
                     {"with_flagged_checks", cell.with_flagged_checks},
                     {"cannot_tell_apart", cell.cannot_tell_apart},
                     {"verdict_counts", cell.verdict_counts},
                     {"effects_named", cell.effects_named},
                     {"noise_findings_named", cell.noise_findings_named},
                     {"checks_flagged", cell.checks_flagged}});
  }
  nlohmann::json pooled = nlohmann::json::array();
  for (const PooledNullRate& rate : result.pooled) {
    pooled.push_back({{"alpha", rate.alpha},
                      {"verdicts", rate.verdicts},
                      {"errors", rate.errors},
                      {"not_explained", rate.not_explained},
                      {"rate", rate.rate},
                      {"rate_stddev", rate.rate_stddev},
                      {"alpha_stddev", rate.alpha_stddev},
                      {"bound", rate.bound},
                      {"within", rate.within}});
  }
  json["cells"] = cells;
  json["pooled"] = pooled;
  json["seconds"] = result.seconds;
  json["threads"] = result.threads;
  return json;
}

int Run(int argc, char** argv) {
  if (!InitProblem("null_rate", kUsage, "problems/null_rate", &argc, &argv)) return kExitBadInput;
  NullRateOptions options;
  Status status = ParseDesigns(FLAGS_designs, &options.designs);
  if (status.ok()) {
    status = ParseNumbers(
        "--noise_factors", FLAGS_noise_factors, [](double x) { return x > 0.0 && x <= 1e4; },
        "(0, 1e4]", &options.noise_factors);
  }
  if (status.ok()) {
    status = ParseNumbers(
        "--alphas", FLAGS_alphas, [](double x) { return x > 0.0 && x < 0.5; }, "(0, 0.5)",
        &options.alphas);
  }
  if (status.ok() && (HasRepeats(options.designs) || HasRepeats(options.noise_factors) ||
                      HasRepeats(options.alphas))) {
    status = Status::Error(
        "--designs, --noise_factors and --alphas must not repeat a value (the pool would count "
        "the same datasets twice)");
  }
  if (status.ok()) status = CheckOutputPaths({{"--json", FLAGS_json}}, RunInputs());
  Scenario course;
  if (status.ok()) status = LoadDefaultScenario(&course);
  if (!status.ok()) return ExitWithError("null_rate", status);
  options.datasets = FLAGS_datasets;
  options.seed = FLAGS_seed;
  options.threads = FLAGS_threads;

  NullRateResult result;
  status = RunNullRateStudy(course, options, &result);
  if (!status.ok()) return ExitWithError("null_rate", status);

  // The header: where the data came from and the command that reproduces it.
  const std::string command = StringPrintf(
      "null_rate --designs=%s --noise_factors=%s --alphas=%s --datasets=%d --seed=%llu",
      JoinNames(options.designs).c_str(), JoinNumbers(options.noise_factors).c_str(),
      JoinNumbers(options.alphas).c_str(), options.datasets,
      static_cast<unsigned long long>(options.seed));
  std::string header = StringPrintf(
      "accelcal null_rate: how often discover says anything but \"explained\" on null data\n"
      "  data     simulated in-process: scenario %s, seed %llu; truth: bias and scale of Table 1,\n"
      "           every other effect neutral, white Gaussian noise of the stated variance (both\n"
      "           scaled by the noise factor)\n",
      course.name.c_str(), static_cast<unsigned long long>(options.seed));
  nlohmann::json designs = nlohmann::json::array();
  for (const std::string& name : options.designs) {
    Scenario scenario;
    MakeNullScenario(course, name, 1.0, &scenario);  // the names were checked above
    // The course's schedule is whatever the scenario says; the others are fixed.
    const std::string tilt =
        NullRateDesignDescription(name) +
        (name == "course" ? ", " + DescribeTilt(scenario.tilt) : std::string());
    header += StringPrintf("  %-8s %s: %s\n", name == options.designs.front() ? "designs" : "",
                           name.c_str(), tilt.c_str());
    designs.push_back({{"name", name}, {"tilt", tilt}});
  }
  header += StringPrintf("  command  %s\n", command.c_str());
  const nlohmann::json json_header = {{"problem", "null_rate"},
                                      {"data", "simulated"},
                                      {"scenario", course.name},
                                      {"seed", options.seed},
                                      {"command", command},
                                      {"designs", designs},
                                      {"noise_factors", options.noise_factors},
                                      {"alphas", options.alphas},
                                      {"datasets_per_cell", options.datasets}};

  std::string json_text;
  if (!FLAGS_json.empty()) status = JsonText(Json(json_header, result), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("null_rate", status);
  std::cout << Table(header, result) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("null_rate", accelcal::Run, argc, argv);
}
