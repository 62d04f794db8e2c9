// triad_study: is the maximum-likelihood triad calibration's uncertainty honest? Simulates
// --trials sessions of one fixed pose set of a known triad (a = T K (u - b), optionally with
// second-order scale terms: v_k = w_k + k2_k w_k^2, docs/triad.md), calibrates each, and
// compares per parameter the spread of the estimates with the mean reported sigma (ratio
// and its standard error ~1/sqrt(2(N-1))), the coverage of the truth at 1, 2, 3 sigma with
// 68.3/95.4/99.7%, and the fit statistic's p < 0.01 rate with 1%. A pose set the
// calibration refuses (planar, six, few) is reported with its refusal, the parameters it
// cannot determine and the poses to add.
//
//   build/bin/triad_study --trials=1000 --scale_nonlinearity --json=triad_study.json

#include <gflags/gflags.h>

#include <cmath>
#include <iostream>
#include <sstream>

#include "common/format.h"
#include "io/csv_reader.h"
#include "io/json_file.h"
#include "problem_support.h"
#include "reporting/triad_study_report.h"
#include "studies/triad_monte_carlo.h"

// clang-format off
DEFINE_int32(trials, 1000, "Simulated sessions (Monte Carlo trials), 10 to 10^7; the verdict makes a claim only with at least 1000.");
DEFINE_uint64(seed, 1, "Seed; trial i uses the noise stream (seed, i), the random pose set its own stream of seed.");
DEFINE_string(pose_set, "random", "The poses of every session: random (--poses directions uniform on the sphere, drawn once), planar (--poses directions turned about the x axis only), six (each axis up and down), few (one pose fewer than the rank needs: 8 random directions, 11 with --scale_nonlinearity). planar, six and few are degenerate: the study reports the refusal.");
DEFINE_int32(poses, 30, "Poses per session for --pose_set=random or planar, 1 to 10000 (six and few fix their own).");
DEFINE_int32(samples_per_pose, 100, "Samples averaged per pose, 2 to 10^6.");
DEFINE_string(noise, "3", "White noise sd per sample, in counts (the output's unit): one value for all axes or three, x,y,z, each in (0, 1e6].");
DEFINE_string(truth, "", "The simulated triad: name=value,... over the default, an Xsens-like triad (misalignment_yz,zy,zx = 0.0035,-0.009,0.021 rad; gain_x,y,z = 1/414.5, 1/412, 1/414.6 (m/s^2)/count; offset_x,y,z = 33124, 33275, 32364 counts; scale_nonlinearity_x,y,z in 1/(m/s^2): 0, or 2e-4,-1e-4,3e-4 with --scale_nonlinearity). A scale_nonlinearity simulated but not estimated is shown as hidden.");
DEFINE_double(g, 9.81744, "Local gravity, m/s^2, in (0, 100).");
DEFINE_bool(scale_nonlinearity, false, "Estimate the second-order scale terms scale_nonlinearity_x,y,z (1/(m/s^2)) too: the 12-parameter fit.");
DEFINE_string(json, "", "Write the results as JSON to this file (atomically).");
ACCELCAL_DEFINE_THREADS_FLAG(0);
ACCELCAL_DEFINE_PROGRESS_FLAG();
// clang-format on
ACCELCAL_FLAG_RANGE(trials, 10, 10000000);
ACCELCAL_FLAG_RANGE(poses, 1, 10000);
ACCELCAL_FLAG_RANGE(samples_per_pose, 2, 1000000);
ACCELCAL_FLAG_OPEN_RANGE(g, 0.0, 100.0);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Checks the maximum-likelihood triad calibration's reported sigma against the spread of its\n"
    "estimates over simulated sessions (Monte Carlo), and the truth's coverage at 1, 2, 3 sigma.\n"
    "Units: angles rad, gains (m/s^2)/count, offsets and noise counts, scale_nonlinearity\n"
    "1/(m/s^2), g m/s^2. Degenerate pose sets are refused, naming what they cannot determine.\n"
    "Exit status: 0 on success (also when the verdict is FAIL: it is a measurement), 2 on bad\n"
    "input (one line on stderr; nothing is written).\n\n"
    "  triad_study [--trials=1000] [--pose_set=random|planar|six|few] [--poses=30]\n"
    "              [--samples_per_pose=100] [--noise=3 | --noise=3,2.5,3.5] "
    "[--truth=gain_x=0.0025,...]\n"
    "              [--scale_nonlinearity] [--g=9.81744] [--seed=1] [--json=FILE] [--threads=0]";

Status ParseNoise(const std::string& text, std::array<double, 3>* noise) {
  std::vector<double> values;
  ACCELCAL_RETURN_IF_ERROR(ParseNumberList(
      "--noise", text, [](double x) { return x > 0.0 && x <= 1e6; },
      "a noise sd in (0, 1e6] counts", &values));
  if (values.size() == 1) values.assign(3, values[0]);
  if (values.size() != 3) {
    return Status::Error("--noise takes one value (all axes) or three (x,y,z), not " +
                         std::to_string(values.size()));
  }
  *noise = {values[0], values[1], values[2]};
  return Status::Ok();
}

constexpr double kMaxTruthAngleRad = 0.1;
constexpr double kMaxTruthOffsetCounts = 1e9;

// --truth: name=value,... over the default; `scale_nonlinearity_given` says whether any k2 was.
Status ParseTruth(const std::string& text, TriadParameters* truth, TriadScaleNonlinearity* k2,
                  bool* scale_nonlinearity_given) {
  *scale_nonlinearity_given = false;
  std::istringstream stream(text);
  for (std::string item; std::getline(stream, item, ',');) {
    const size_t equals = item.find('=');
    const std::string name = item.substr(0, equals);
    double value;
    if (equals == std::string::npos || !ParseFiniteNumber(item.substr(equals + 1), &value)) {
      return Status::Error("--truth: '" + item.substr(0, 60) +
                           "' is not name=value with a finite number");
    }
    bool known = false;
    for (int p = 0; p < kTriadParameterCount; ++p) {
      if (name == TriadParameterInfos()[p].name) {
        (*truth)[p] = value;
        known = true;
      }
    }
    for (int k = 0; k < kTriadScaleNonlinearityCount; ++k) {
      if (name == TriadScaleNonlinearityInfos()[k].name) {
        (*k2)[k] = value;
        known = *scale_nonlinearity_given = true;
      }
    }
    if (!known) {
      return Status::Error("--truth: unknown parameter '" + name.substr(0, 40) +
                           "' (known: misalignment_yz/zy/zx, gain_x/y/z, offset_x/y/z, "
                           "scale_nonlinearity_x/y/z)");
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (!((*truth)[kTriadGainX + k] > 0.0)) {
      return Status::Error(std::string("--truth: ") + TriadParameterInfos()[kTriadGainX + k].name +
                           " must be positive ((m/s^2)/count)");
    }
  }
  // The model's angles are a small non-orthogonality, and the fit starts from 0: a truth of
  // radians would be a study of a local minimum, not of the sigma. Offsets beyond 1e9 counts
  // put the outputs where a double's resolution nears the noise.
  for (int p = 0; p < kTriadParameterCount; ++p) {
    const bool angle = p < kTriadGainX;
    const bool offset = p >= kTriadOffsetX && p <= kTriadOffsetZ;
    const double bound = angle ? kMaxTruthAngleRad : kMaxTruthOffsetCounts;
    if ((angle || offset) && !(std::abs((*truth)[p]) <= bound)) {
      return Status::Error(
          StringPrintf("--truth: %s=%g is outside [-%g, %g] %s%s", TriadParameterInfos()[p].name,
                       (*truth)[p], bound, bound, angle ? "rad" : "counts",
                       angle ? " (a non-orthogonality of at most 5.7 degrees)" : ""));
    }
  }
  return Status::Ok();
}

Status OptionsFromFlags(TriadMonteCarloOptions* options, DataSource* source) {
  ACCELCAL_RETURN_IF_ERROR(
      ParseTriadPoseSet(FLAGS_pose_set, &options->pose_set).WithContext("--pose_set"));
  const bool fixed_count =
      options->pose_set == TriadPoseSet::kSix || options->pose_set == TriadPoseSet::kFew;
  if (fixed_count && !gflags::GetCommandLineFlagInfoOrDie("poses").is_default) {
    return Status::Error("--poses applies only to --pose_set=random or planar; --pose_set=" +
                         FLAGS_pose_set + " fixes its own count");
  }
  ACCELCAL_RETURN_IF_ERROR(ParseNoise(FLAGS_noise, &options->noise_stddev));
  options->scale_nonlinearity = FLAGS_scale_nonlinearity;
  if (options->scale_nonlinearity) options->truth_scale_nonlinearity = ExampleScaleNonlinearity();
  bool k2_given = false;
  ACCELCAL_RETURN_IF_ERROR(
      ParseTruth(FLAGS_truth, &options->truth, &options->truth_scale_nonlinearity, &k2_given));
  options->trials = FLAGS_trials;
  options->seed = FLAGS_seed;
  options->poses = FLAGS_poses;
  options->samples_per_pose = FLAGS_samples_per_pose;
  options->gravity_mps2 = FLAGS_g;
  options->threads = FLAGS_threads;

  source->simulated = true;
  source->seed = FLAGS_seed;
  source->scenario = StringPrintf(
      "triad (%s truth, pose set %s%s, %d samples per pose)",
      FLAGS_truth.empty() ? "Xsens-like" : "given", FLAGS_pose_set.c_str(),
      fixed_count ? "" : StringPrintf(" of %d", FLAGS_poses).c_str(), FLAGS_samples_per_pose);
  if (!options->scale_nonlinearity) {
    for (int k = 0; k < kTriadScaleNonlinearityCount; ++k) {
      if (options->truth_scale_nonlinearity[k] != 0.0) {
        source->hidden.emplace_back(TriadScaleNonlinearityInfos()[k].name,
                                    options->truth_scale_nonlinearity[k]);
      }
    }
  }
  return Status::Ok();
}

int Run(int argc, char** argv) {
  if (!InitProblem("triad_study", kUsage, "problems/triad_study", &argc, &argv))
    return kExitBadInput;
  TriadStudyReport report;
  DataSource source;
  ProgressStyle progress_style;
  Status status = OptionsFromFlags(&report.options, &source);
  if (status.ok()) status = ProgressStyleFromFlag(FLAGS_progress, &progress_style);
  if (status.ok()) status = CheckOutputPaths({{"--json", FLAGS_json}}, RunInputs());
  ProgressPrinter progress("triad_study", "trials", progress_style, &std::cerr);
  report.options.progress = progress.Callback();
  if (status.ok()) status = RunTriadMonteCarlo(report.options, &report.result);
  std::string json_text;
  if (status.ok() && !FLAGS_json.empty())
    status = JsonText(WithProvenance(TriadStudyJson(report), source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("triad_study", status);
  std::cout << WithDataLine(source, TriadStudyText(report)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("triad_study", accelcal::Run, argc, argv);
}
