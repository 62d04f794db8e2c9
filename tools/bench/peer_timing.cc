// peer_timing: accelcal's side of the side-by-side comparison with numpy/SciPy
// (tools/bench/peers.sh, issue 9). It loads a data folder once, then times in-process, with
// std::chrono::steady_clock, each solve a researcher would otherwise write in numpy/SciPy:
//
//   baseline_closed_form  bias and scale per axis from streaming sufficient statistics
//                         (estimation/tilt_table/linear_ls.h), with sigma^2 (A^T A)^-1
//   baseline_ceres        the same problem as whitened Ceres residuals and ceres::Covariance
//                         (estimation/tilt_table/ceres_linear_ls.h)
//   joint                 bias and scale plus --effects, every tilt-test sample through the
//                         spec's full model and the run's endpoint tied to --landmark, with
//                         ceres::Covariance (estimation/tilt_table/joint_estimator.h, SolveJoint)
//
// Each time is the median over at most --repetitions solves; loading the files is outside
// the clock. The JSON holds the times and every estimate (values, sigmas, covariance,
// chi-square), so tools/bench/peers.py can check that the peers solved the same problem.
//
//   build/bin/peer_timing --data_dir=../shared/data/tp2-2018 --repetitions=21 --json=cc.json

#include <gflags/gflags.h>
#include <glog/logging.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "estimation/tilt_table/ceres_linear_ls.h"
#include "estimation/tilt_table/joint_estimator.h"
#include "estimation/tilt_table/linear_ls.h"
#include "estimation/tilt_table/parameter_estimate.h"
#include "io/atomic_file.h"
#include "io/course_data.h"
#include "models/tilt_table.h"
#include "reporting/estimate_json.h"

DEFINE_string(data_dir, "",
              "Folder with the course layout or the CSV layout (tilt test, run, landmarks, "
              "conditions).");
DEFINE_string(calibration_file, "",
              "A tilt test (.mat or .csv) replacing the folder's, e.g. a large simulated one; the "
              "run, landmarks and conditions still come from --data_dir.");
DEFINE_int32(repetitions, 11, "Solves per problem (>= 1); the reported time is their median.");
DEFINE_double(time_budget, 30.0,
              "Stop repeating a problem once its solves have taken this long in total (s, > 0); "
              "at least one solve is always timed.");
DEFINE_string(problems, "baseline_closed_form,baseline_ceres,joint",
              "Comma-separated problems to time: baseline_closed_form, baseline_ceres, joint.");
DEFINE_string(effects, "angle_offset,nonorthogonality",
              "The joint problem's effects beyond bias and scale (as joint --effects).");
DEFINE_string(landmark, "C", "The landmark the joint problem ties the run to.");
DEFINE_string(json, "-", "Where to write the JSON result (atomically); '-': stdout.");

namespace accelcal {
namespace {

constexpr int kExitBadInput = 2;

struct Inputs {
  CourseData data;
  DataFiles files;
  double gravity_mps2 = kCourseGravityMps2;
};

// Times `solve` up to FLAGS_repetitions times (fewer once FLAGS_time_budget is spent) and
// records every duration in seconds. The solve's own result is kept by the caller's lambda;
// a failure stops the repetitions and is returned.
Status TimeRepeatedly(const std::function<Status()>& solve, std::vector<double>* seconds) {
  seconds->clear();
  double total_s = 0.0;
  for (int repetition = 0; repetition < FLAGS_repetitions; ++repetition) {
    if (repetition > 0 && total_s >= FLAGS_time_budget) break;
    const auto start = std::chrono::steady_clock::now();
    const Status status = solve();
    const auto stop = std::chrono::steady_clock::now();
    ACCELCAL_RETURN_IF_ERROR(status);
    const double elapsed_s = std::chrono::duration<double>(stop - start).count();
    seconds->push_back(elapsed_s);
    total_s += elapsed_s;
  }
  return Status::Ok();
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

nlohmann::json Timing(const std::vector<double>& seconds) {
  return {{"seconds_median", Median(seconds)},
          {"seconds", seconds},
          {"repetitions", static_cast<int>(seconds.size())}};
}

nlohmann::json BaselineJson(const BaselineFit& fit) {
  nlohmann::json json = ParameterEstimateJson(FromBaselineFit(fit));
  json["chi2_x"] = fit.chi2_x.chi2;
  json["chi2_y"] = fit.chi2_y.chi2;
  return json;
}

Status Load(Inputs* inputs) {
  if (FLAGS_data_dir.empty()) {
    return Status::Error(
        "--data_dir is required (the run, landmarks and conditions are read "
        "from it)");
  }
  DataFiles overrides;
  overrides.calibration = FLAGS_calibration_file;
  ACCELCAL_RETURN_IF_ERROR(ResolveDataFiles(FLAGS_data_dir, overrides, &inputs->files));
  ACCELCAL_RETURN_IF_ERROR(LoadDataFiles(inputs->files, &inputs->data));
  // As the problem binaries do without --g: the data's own g when scenario.json states it,
  // else the course's 9.8 m/s^2 (datos.txt never states it).
  if (inputs->data.conditions.has_gravity)
    inputs->gravity_mps2 = inputs->data.conditions.gravity_mps2;
  return Status::Ok();
}

bool Wanted(const std::string& problem) {
  const std::string list = "," + FLAGS_problems + ",";
  return list.find("," + problem + ",") != std::string::npos;
}

Status TimeProblems(const Inputs& inputs, nlohmann::json* json) {
  const CourseData& data = inputs.data;
  LinearLsOptions linear = LinearLsOptionsFor(data.conditions, inputs.gravity_mps2);

  if (Wanted("baseline_closed_form")) {
    BaselineFit fit;
    std::vector<double> seconds;
    ACCELCAL_RETURN_IF_ERROR(
        TimeRepeatedly([&] { return EstimateLinearLs(data.test, linear, &fit); }, &seconds)
            .WithContext("baseline_closed_form"));
    (*json)["problems"]["baseline_closed_form"] = BaselineJson(fit);
    (*json)["problems"]["baseline_closed_form"]["timing"] = Timing(seconds);
  }

  if (Wanted("baseline_ceres")) {
    CeresLinearLsOptions options;
    options.model = linear;
    CeresLinearLsResult result;
    std::vector<double> seconds;
    ACCELCAL_RETURN_IF_ERROR(
        TimeRepeatedly([&] { return EstimateLinearLsWithCeres(data.test, options, &result); },
                       &seconds)
            .WithContext("baseline_ceres"));
    (*json)["problems"]["baseline_ceres"] = BaselineJson(result.fit);
    (*json)["problems"]["baseline_ceres"]["timing"] = Timing(seconds);
    (*json)["problems"]["baseline_ceres"]["iterations"] = result.solver.iterations;
  }

  if (Wanted("joint")) {
    JointOptions options;
    ACCELCAL_RETURN_IF_ERROR(
        ParseEffects(FLAGS_effects, &options.effects).WithContext("--effects"));
    options.gravity_mps2 = inputs.gravity_mps2;
    options.noise_variance_x = data.conditions.noise_variance_x;
    options.noise_variance_y = data.conditions.noise_variance_y;
    options.landmark_mode = JointOptions::Landmark::kNamed;
    options.landmark_name = FLAGS_landmark;
    JointResult result;
    std::vector<double> seconds;
    ACCELCAL_RETURN_IF_ERROR(TimeRepeatedly(
                                 [&] {
                                   return SolveJoint(data.test, data.run, data.conditions,
                                                     data.landmarks, options, &result);
                                 },
                                 &seconds)
                                 .WithContext("joint"));
    const ParameterEstimate& estimate = result.estimate;
    nlohmann::json& joint = (*json)["problems"]["joint"];
    joint = ParameterEstimateJson(estimate);
    joint["effects"] = FLAGS_effects;
    joint["landmark"] = result.landmark;
    joint["chi2_x"] = result.chi2_x;
    joint["chi2_y"] = result.chi2_y;
    joint["chi2_endpoint"] = result.chi2_endpoint;
    joint["iterations"] = result.solver.iterations;
    joint["timing"] = Timing(seconds);
  }
  return Status::Ok();
}

int Run(int argc, char** argv) {
  gflags::SetUsageMessage(
      "Times accelcal's baseline (closed form and Ceres) and joint solve in-process on one data "
      "folder, excluding loading, and writes the times and estimates as JSON.\n"
      "  peer_timing --data_dir=../shared/data/tp2-2018 --repetitions=21 --json=cc.json");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = google::GLOG_WARNING;
  google::InitGoogleLogging(argv[0]);
  auto fail = [](const Status& status) {
    std::cerr << "peer_timing: error: " << status.message() << "\n";
    return kExitBadInput;
  };
  if (argc > 1) return fail(Status::Error(std::string("unexpected argument '") + argv[1] + "'"));
  if (FLAGS_repetitions < 1) return fail(Status::Error("--repetitions must be at least 1"));
  if (!(FLAGS_time_budget > 0.0)) return fail(Status::Error("--time_budget must be positive (s)"));

  Inputs inputs;
  Status status = Load(&inputs);
  if (!status.ok()) return fail(status);
  const CourseData& data = inputs.data;
  nlohmann::json json;
  json["timing"] = {{"clock", "std::chrono::steady_clock"},
                    {"statistic", "median over repetitions"},
                    {"excludes", "loading the files"},
                    {"threads", 1}};
  json["data"] = {
      {"calibration_file", inputs.files.calibration},
      {"run_file", inputs.files.run},
      {"tilt_samples", data.test.size()},
      {"run_samples", data.run.size()},
      {"gravity", inputs.gravity_mps2},
      {"noise_variance", {data.conditions.noise_variance_x, data.conditions.noise_variance_y}}};
  status = TimeProblems(inputs, &json);
  if (!status.ok()) return fail(status);

  const std::string text = json.dump(2) + "\n";
  if (FLAGS_json.empty() || FLAGS_json == "-") {
    std::cout << text << std::flush;
  } else {
    status = WriteFileAtomically(FLAGS_json, text).WithContext("--json");
    if (!status.ok()) return fail(status);
  }
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) { return accelcal::Run(argc, argv); }
