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

#include "io/csv_reader.h"
#include "io/json_file.h"
#include "io/scenario_json.h"
#include "problem_support.h"
#include "reporting/null_rate_report.h"
#include "studies/null_rate_study.h"

// clang-format off
DEFINE_string(designs, "course,n2000,eight_positions,half_circle", "Tilt-test designs, comma-separated: course (the tp2-2018 scenario's 20001 samples over [0, 2 pi]), n2000 (2000 uniform over [0, 2 pi)), eight_positions (2000 at 8 static positions), half_circle (2000 uniform over [0, pi]).");
DEFINE_string(noise_factors, "0.25,1,4", "Factors on the stated (and true) noise variances, comma-separated, in (0, 1e4].");
DEFINE_string(alphas, "0.01,0.05", "Discovery's alpha values, comma-separated, each in (0, 0.5); the same datasets serve every alpha.");
DEFINE_int32(datasets, 170, "Null datasets per (design, noise factor); the default gives 2040 per alpha over the 12 default cells.");
// clang-format on
DEFINE_uint64(seed, 1, "Seed; dataset i of a cell uses the noise streams of (seed, cell, i).");
ACCELCAL_DEFINE_THREADS_FLAG(2);
DEFINE_string(json, "", "Write the table as JSON to this file (atomically).");
ACCELCAL_DEFINE_PROGRESS_FLAG();
ACCELCAL_FLAG_RANGE(datasets, 10, 10000000);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Measures discovery's false-discovery rate: the fraction of null datasets (bias and scale\n"
    "only, white noise of the stated variance) whose verdict is not \"explained\", per design,\n"
    "noise level and alpha, and pooled per alpha against alpha + 2 Monte Carlo sd.\n"
    "Exit status: 0 on success (also when the rate is above the bound), 2 on bad input.\n\n"
    "  null_rate [--designs=course,n2000] [--noise_factors=0.25,1,4] [--alphas=0.01,0.05]\n"
    "            [--datasets=170] [--threads=2] [--json=null_rate.json] [--progress=always]";

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

// The study's options from the flags: the lists parsed and checked, no value repeated.
Status OptionsFromFlags(NullRateOptions* options) {
  ACCELCAL_RETURN_IF_ERROR(ParseDesigns(FLAGS_designs, &options->designs));
  ACCELCAL_RETURN_IF_ERROR(ParseNumberList(
      "--noise_factors", FLAGS_noise_factors, [](double x) { return x > 0.0 && x <= 1e4; },
      "a number in (0, 1e4]", &options->noise_factors));
  ACCELCAL_RETURN_IF_ERROR(ParseNumberList(
      "--alphas", FLAGS_alphas, [](double x) { return x > 0.0 && x < 0.5; }, "a number in (0, 0.5)",
      &options->alphas));
  if (HasRepeats(options->designs) || HasRepeats(options->noise_factors) ||
      HasRepeats(options->alphas)) {
    // clang-format off
    return Status::Error("--designs, --noise_factors and --alphas must not repeat a value (the pool would count the same datasets twice)");
    // clang-format on
  }
  options->datasets = FLAGS_datasets;
  options->seed = FLAGS_seed;
  options->threads = FLAGS_threads;
  return Status::Ok();
}

int Run(int argc, char** argv) {
  if (!InitProblem("null_rate", kUsage, "problems/null_rate", &argc, &argv)) return kExitBadInput;
  NullRateReport report;
  std::string json_text;
  ProgressStyle progress_style;
  Status status = OptionsFromFlags(&report.options);
  if (status.ok()) status = ProgressStyleFromFlag(FLAGS_progress, &progress_style);
  DataSource source;
  if (status.ok()) {
    status = LoadSimulationScenario("", "", FLAGS_seed, {{"--json", FLAGS_json}}, &report.course,
                                    &source);
  }
  ProgressPrinter progress("null_rate", "datasets", progress_style, &std::cerr);
  report.options.progress = progress.Callback();
  if (status.ok()) status = RunNullRateStudy(report.course, report.options, &report.study);
  if (status.ok() && !FLAGS_json.empty())
    status = JsonText(WithProvenance(NullRateJson(report), source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("null_rate", status);
  std::cout << WithDataLine(source, NullRateText(report)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("null_rate", accelcal::Run, argc, argv);
}
