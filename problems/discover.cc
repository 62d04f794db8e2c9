// discover: does the baseline model explain the measured data, and if not, what is
// missing? Fits the baseline, analyses the noise per axis (level, correlation, outliers,
// tails), then scores every effect of the catalogue (score test, 1 dof each, Holm at
// --alpha), adds the strongest, refits the joint problem in Ceres, and repeats; checks what
// the final model leaves and which named effect another candidate would replace. Reports
// one of four verdicts (explained, missing, unexplained, cannot_tell_apart), each named
// effect +- sigma and what adding it gains (delta chi2, BIC, cross-validation, the
// endpoint before and after).
//
//   build/bin/discover --data_dir=../shared/data/tp2-2018 --json=discover.json \
//       --bins_csv=bins.csv --residuals_csv=residuals.csv

#include <gflags/gflags.h>

#include <iostream>

#include "estimation/tilt_table/discovery.h"
#include "io/atomic_file.h"
#include "io/course_data.h"
#include "io/json_file.h"
#include "problem_support.h"
#include "reporting/discovery_report.h"

// clang-format off
DEFINE_string(data_dir, "", "Folder with the course layout or the CSV layout. Empty (and no --*_file): simulate the embedded tp2-2018 scenario.");
ACCELCAL_DEFINE_DATA_FILE_FLAGS();
DEFINE_string(set, "", "Without data: effects hidden in the simulated scenario, name=value,... (as simulate --set), e.g. --set=angle_offset=0.004.");
// clang-format on
DEFINE_uint64(seed, 1, "Without data: the seed of the simulation.");
ACCELCAL_DEFINE_THETA_UNIT_FLAG();
DEFINE_double(alpha, 0.01, "Family-wise error rate of each step (Holm), in (0, 0.5).");
DEFINE_double(g, 9.8, "Gravity in m/s^2, 1 to 100.");
DEFINE_int32(bins, 36, "Bins of the residual against theta, 4 to 1000.");
DEFINE_int32(folds, 5,
             "Cross-validation folds over contiguous theta blocks: 0 (none) or 2 to 100.");
DEFINE_string(json, "", "Write the results as JSON to this file (atomically).");
// clang-format off
DEFINE_string(bins_csv, "", "Write the binned residuals and the named effects' signatures as CSV (for tools/plot_discovery.py).");
DEFINE_string(residuals_csv, "", "Write the final model's tilt-test residual per sample as CSV (at most 5000 rows, evenly spread; for tools/plot_discovery.py --residuals_csv).");
// clang-format on
ACCELCAL_DEFINE_THREADS_FLAG(1);
ACCELCAL_FLAG_OPEN_RANGE(alpha, 0.0, 0.5);
ACCELCAL_FLAG_RANGE(g, 1.0, 100.0);
ACCELCAL_FLAG_RANGE(bins, 4, 1000);
ACCELCAL_FLAG_RANGE(folds, 0, 100);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Tells whether the baseline (bias and scale per axis) explains the data and, if not, what is\n"
    "missing, how large (in the spec's units), and what adding it gains. The verdict is one of:\n"
    "  explained          the baseline explains the data; nothing remains that the checks see\n"
    "  missing            effects (or a noise model) of the catalogue are missing; with them the\n"
    "                     model explains the data\n"
    "  unexplained        structure remains that no effect of the catalogue explains\n"
    "  cannot_tell_apart  a named effect and another candidate explain the data about equally\n"
    "                     well; the report says what would separate them\n"
    "Exit status: 0 on success, 2 on bad input (one line on stderr; nothing is written).\n\n"
    "  discover --data_dir=../shared/data/tp2-2018 [--alpha=0.01] [--json=discover.json]";

using Inputs = Experiment;

Status Load(Inputs* inputs) {
  LoadOptions options;
  ACCELCAL_RETURN_IF_ERROR(LoadOptionsFromFlags(FLAGS_theta_unit, &options));
  return LoadExperiment(ACCELCAL_DATA_FLAGS(), FLAGS_set, FLAGS_seed, {"set", "seed"}, options,
                        {{"--json", FLAGS_json},
                         {"--bins_csv", FLAGS_bins_csv},
                         {"--residuals_csv", FLAGS_residuals_csv}},
                        inputs);
}

int Run(int argc, char** argv) {
  if (!InitProblem("discover", kUsage, "problems/discover", &argc, &argv)) return kExitBadInput;
  Status status;
  if (FLAGS_folds == 1) status = Status::Error("--folds must be 0 (none) or 2 to 100");
  Inputs inputs;
  if (status.ok()) status = Load(&inputs);
  DiscoveryOptions options;
  options.alpha = FLAGS_alpha;
  options.gravity_mps2 = ChooseGravity(inputs.conditions, FLAGS_g);
  options.theta_bins = FLAGS_bins;
  options.cross_validation_folds = FLAGS_folds;
  options.num_threads = ThreadCount(FLAGS_threads);
  DiscoveryResult result;
  if (status.ok())
    status =
        Discover(inputs.test, inputs.run, inputs.conditions, inputs.landmarks, options, &result);
  if (!status.ok()) return ExitWithError("discover", status);
  std::string json_text;
  if (!FLAGS_json.empty())
    status = JsonText(WithProvenance(DiscoveryJson(result, FLAGS_alpha), inputs.data_source),
                      &json_text);
  if (status.ok()) {
    status = WriteOutputFiles(
        {{FLAGS_json, json_text},
         {FLAGS_bins_csv, FLAGS_bins_csv.empty() ? "" : DiscoveryBinsCsv(result)},
         {FLAGS_residuals_csv,
          FLAGS_residuals_csv.empty() ? "" : DiscoveryResidualsCsv(result, inputs.test)}});
  }
  if (!status.ok()) return ExitWithError("discover", status);
  std::cout << WithDataLine(inputs.data_source, DiscoveryText(result, FLAGS_alpha)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("discover", accelcal::Run, argc, argv);
}
