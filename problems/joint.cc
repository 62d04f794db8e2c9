// joint: the extended error model in one nonlinear Ceres problem, beside the linear
// baseline. Bias and scale of each axis plus any effects of the catalogue are fitted to
// every tilt-test sample and, when the run is tied to a landmark, to the dead-reckoned
// endpoint; the covariance comes from ceres::Covariance on the whitened problem.
//
//   m_k,i = (1 + s_k) f_along_k(theta_i + delta, eps) + k2_k f^2 + b_k + d_k u_i + noise
//   p_end(params) = p0 + v0 T + sum_j w_j a_j(params)  ~  landmark,  a_j = model^-1(m_j)
//
//   build/bin/joint --data_dir=../shared/data/tp2-2018 --effects=angle_offset,nonorthogonality \
//       --landmark=auto --json=joint.json

#include <gflags/gflags.h>

#include <cmath>
#include <iostream>

#include "estimation/tilt_table/joint_estimator.h"
#include "estimation/tilt_table/linear_ls.h"
#include "io/atomic_file.h"
#include "io/course_data.h"
#include "io/json_file.h"
#include "problem_support.h"
#include "reporting/joint_report.h"

// clang-format off
DEFINE_string(data_dir, "", "Folder with the course layout or the CSV layout. Empty (and no --*_file): simulate the embedded tp2-2018 scenario.");
// clang-format on
ACCELCAL_DEFINE_DATA_FILE_FLAGS();
DEFINE_string(
    set, "",
    "Without data: overrides of the simulated scenario, name=value,... (as simulate --set).");
DEFINE_uint64(seed, 1, "Without data: the seed of the simulation.");
ACCELCAL_DEFINE_THETA_UNIT_FLAG();
namespace {
// The help text of --effects, from the catalogue (gflags keeps the pointer).
const char* EffectsHelp() {
  static const std::string help = "Effects to estimate beyond bias and scale, comma-separated: " +
                                  accelcal::EstimableEffectsText() + "; 'all'; empty: none.";
  return help.c_str();
}
}  // namespace
DEFINE_string(effects, "", EffectsHelp());
// clang-format off
DEFINE_string(landmark, "auto", "NAME: tie the run's endpoint to that landmark; auto: solve once per landmark and report each hypothesis' posterior; none: leave the run out.");
// clang-format on
DEFINE_double(landmark_sigma, 0.0, "The landmarks' position uncertainty (m, >= 0).");
DEFINE_string(loss, "none", "Robust loss on the tilt-test residuals: none, huber or cauchy.");
DEFINE_double(loss_scale, 1.345, "The robust loss' scale, in units of sigma (> 0).");
DEFINE_double(g, 9.8, "Gravity in m/s^2.");
DEFINE_double(landmark_alpha, 0.01,
              "Significance level of the landmark decision on each endpoint, in (0, 1): the most "
              "probable landmark counts as reached only if its chi-square(2) p-value is at least "
              "this.");
ACCELCAL_RENAMED_FLAG(alpha, landmark_alpha);
DEFINE_string(json, "", "Write both solutions as JSON to this file (atomically).");
ACCELCAL_DEFINE_THREADS_FLAG(1);
// clang-format off
DEFINE_int32(max_iterations, 100, "Levenberg-Marquardt iterations before the solve counts as not converged, 1 to 10000.");
// clang-format on
ACCELCAL_FLAG_RANGE(landmark_sigma, 0.0, 1e6);
ACCELCAL_FLAG_RANGE(loss_scale, 1e-3, 1e3);
ACCELCAL_FLAG_RANGE(g, 1.0, 100.0);
ACCELCAL_FLAG_OPEN_RANGE(landmark_alpha, 0.0, 1.0);
ACCELCAL_FLAG_RANGE(max_iterations, 1, 10000);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Fits the joint nonlinear error model (bias and scale per axis plus chosen effects, in the\n"
    "spec's units) to the tilt test and the run tied to a landmark, and prints it beside the\n"
    "linear baseline with every parameter +- 1 sigma, the shift in sigmas, chi-square per\n"
    "residual group, and the endpoint (m) with its landmark table.\n"
    "Exit status: 0 on success, 2 on bad input or a problem that is not identifiable.\n\n"
    // clang-format off
    "  joint --data_dir=../shared/data/tp2-2018 --effects=angle_offset,nonorthogonality --landmark=auto";
// clang-format on

using Inputs = Experiment;

Status Load(Inputs* inputs) {
  LoadOptions options;
  ACCELCAL_RETURN_IF_ERROR(LoadOptionsFromFlags(FLAGS_theta_unit, &options));
  return LoadExperiment(ACCELCAL_DATA_FLAGS(), FLAGS_set, FLAGS_seed, {"set", "seed"}, options,
                        {{"--json", FLAGS_json}}, inputs);
}

Status Options(const Inputs& inputs, JointOptions* options) {
  *options = JointOptionsFor(inputs.conditions, ChooseGravity(inputs.conditions, FLAGS_g));
  ACCELCAL_RETURN_IF_ERROR(ParseRobustLoss(FLAGS_loss, &options->loss));
  ACCELCAL_RETURN_IF_ERROR(ParseEffects(FLAGS_effects, &options->effects).WithContext("--effects"));
  if (FLAGS_landmark == "none") {
    options->landmark_mode = JointOptions::Landmark::kNone;
  } else if (FLAGS_landmark == "auto") {
    options->landmark_mode = JointOptions::Landmark::kAuto;
  } else {
    options->landmark_mode = JointOptions::Landmark::kNamed;
    options->landmark_name = FLAGS_landmark;
  }
  options->landmark_sigma_m = FLAGS_landmark_sigma;
  options->loss_scale = FLAGS_loss_scale;
  options->num_threads = ThreadCount(FLAGS_threads);
  options->max_iterations = FLAGS_max_iterations;
  return Status::Ok();
}

Status Solve(const Inputs& inputs, const JointOptions& options, JointReport* report) {
  const LinearLsOptions linear = LinearLsOptionsFor(inputs.conditions, options.gravity_mps2);
  ACCELCAL_RETURN_IF_ERROR(EstimateLinearLs(inputs.test, linear, &report->linear));
  TrajectoryOptions trajectory;
  trajectory.path_stride = inputs.run.size();
  ACCELCAL_RETURN_IF_ERROR(DeadReckon(inputs.run, inputs.conditions, report->linear, trajectory,
                                      &report->linear_trajectory));
  report->linear_decision =
      DecideLandmark(report->linear_trajectory.endpoint, report->linear_trajectory.covariance,
                     inputs.landmarks, FLAGS_landmark_alpha);
  const Status solved = SolveJoint(inputs.test, inputs.run, inputs.conditions, inputs.landmarks,
                                   options, &report->joint);
  if (!solved.ok() && solved.message().find("Maximum number of iterations") != std::string::npos)
    return Status::Error(solved.message() + "; raise --max_iterations or estimate fewer effects");
  ACCELCAL_RETURN_IF_ERROR(solved);
  ACCELCAL_RETURN_IF_ERROR(DeadReckon(inputs.run, inputs.conditions, report->joint.estimate,
                                      trajectory, &report->joint_trajectory));
  report->joint_decision =
      DecideLandmark(report->joint_trajectory.endpoint, report->joint_trajectory.covariance,
                     inputs.landmarks, FLAGS_landmark_alpha);
  return Status::Ok();
}

int Run(int argc, char** argv) {
  if (!InitProblem("joint", kUsage, "problems/joint", &argc, &argv)) return kExitBadInput;
  Inputs inputs;
  JointOptions options;
  JointReport report;
  Status status = Load(&inputs);
  if (status.ok()) status = Options(inputs, &options);
  if (status.ok()) status = Solve(inputs, options, &report);
  if (!status.ok()) return ExitWithError("joint", status);
  std::string json_text;
  if (!FLAGS_json.empty())
    status = JsonText(WithProvenance(JointJson(report), inputs.data_source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("joint", status);
  std::cout << WithDataLine(inputs.data_source, JointTable(report, FLAGS_v >= 1)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("joint", accelcal::Run, argc, argv);
}
