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
#include "studies/triad_discovery_study.h"
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
DEFINE_double(discovery_alpha, 0.0, "Instead of the sigma study: the discovery null/power study at this alpha (family-wise error rate, in (0, 0.5)): --trials whole sessions of --poses holds, simulated sample by sample with the noise of --noise and --flicker_b, calibrated as calibrate_imu --mode=ml does on their true holds; counts the verdicts and what discovery named beyond the noise (0: the sigma study).");
DEFINE_string(flicker_b, "0", "Discovery study: flicker (bias instability) noise added to every sample, as its Allan term B in counts, one value or three (x,y,z); the Allan deviation's floor is 0.664 B (allan --static=all fits B 0.57, 0.59, 0.81 on imu_tk's Xsens log). Simulated per axis as one continuous series over the session, a bank of Gauss-Markov processes at correlation times spaced by 4 over --flicker_band. 0: none.");
DEFINE_string(flicker_band, "0.02,1400", "Discovery study: the flicker bank's correlation times, s: min,max (0 < min <= max <= 1e5); the bank runs from min by factors of 4 up to max (default: 0.02 to 1311 s, a flat Allan deviation from 0.1 s to beyond the session, as the Xsens log's within-pose Allan fit gives: B and no random walk).");
DEFINE_string(offset_drift, "0", "Discovery study: a hidden linear offset drift in counts/s, one value or three (x,y,z) (power: how often discovery names offset_drift_x/y/z).");
DEFINE_double(hold_s, 8.0, "Discovery study: each hold's duration, s (hold_s times rate_hz at least 2 samples).");
DEFINE_double(turn_s, 5.5, "Discovery study: each turn between holds, s, in (0, 1000].");
DEFINE_double(rate_hz, 100.0, "Discovery study: sample rate, Hz, in (0, 1e5].");
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
    "              [--scale_nonlinearity] [--g=9.81744] [--seed=1] [--json=FILE] [--threads=0]\n\n"
    "With --discovery_alpha, the null/power study of the triad's discovery instead (issue 33):\n"
    "whole sessions with white noise (--noise, counts per sample), flicker noise (--flicker_b,\n"
    "the Allan term B in counts) and a hidden offset drift (--offset_drift, counts/s), e.g. the\n"
    "Xsens log's own noise:\n"
    "  triad_study --discovery_alpha=0.01 --trials=400 --poses=38 --noise=3.3,3.2,3.25 \\\n"
    "              --flicker_b=0.57,0.59,0.81 --seed=1";

// One value (all axes) or three (x,y,z), each accepted by `ok`.
Status ParseAxes(const char* flag, const std::string& text, bool (*ok)(double), const char* what,
                 std::array<double, 3>* axes) {
  std::vector<double> values;
  ACCELCAL_RETURN_IF_ERROR(ParseNumberList(flag, text, ok, what, &values));
  if (values.size() == 1) values.assign(3, values[0]);
  if (values.size() != 3) {
    return Status::Error(std::string(flag) + " takes one value (all axes) or three (x,y,z), not " +
                         std::to_string(values.size()));
  }
  *axes = {values[0], values[1], values[2]};
  return Status::Ok();
}

Status ParseNoise(const std::string& text, std::array<double, 3>* noise) {
  return ParseAxes(
      "--noise", text, [](double x) { return x > 0.0 && x <= 1e6; },
      "a noise sd in (0, 1e6] counts", noise);
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
  for (const char* flag :
       {"flicker_b", "flicker_band", "offset_drift", "hold_s", "turn_s", "rate_hz"}) {
    if (!gflags::GetCommandLineFlagInfoOrDie(flag).is_default) {
      return Status::Error(std::string("--") + flag +
                           " applies only to the discovery study (--discovery_alpha)");
    }
  }
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

// --discovery_alpha: the discovery null/power study.
Status DiscoveryOptionsFromFlags(TriadDiscoveryStudyOptions* options, DataSource* source) {
  ACCELCAL_RETURN_IF_ERROR(ParseNoise(FLAGS_noise, &options->noise_stddev));
  ACCELCAL_RETURN_IF_ERROR(ParseAxes(
      "--flicker_b", FLAGS_flicker_b, [](double x) { return x >= 0.0 && x <= 1e6; },
      "a flicker B in [0, 1e6] counts", &options->flicker_b));
  ACCELCAL_RETURN_IF_ERROR(ParseAxes(
      "--offset_drift", FLAGS_offset_drift, [](double x) { return std::abs(x) <= 1e6; },
      "an offset drift in [-1e6, 1e6] counts/s", &options->offset_drift));
  std::vector<double> band;
  ACCELCAL_RETURN_IF_ERROR(ParseNumberList(
      "--flicker_band", FLAGS_flicker_band, [](double x) { return x > 0.0 && x <= 1e5; },
      "a correlation time in (0, 1e5] s", &band));
  if (band.size() != 2 || band[0] > band[1])
    return Status::Error("--flicker_band takes two times, min,max, with min <= max (s)");
  options->flicker_min_s = band[0];
  options->flicker_max_s = band[1];
  if (!(FLAGS_discovery_alpha > 0.0 && FLAGS_discovery_alpha < 0.5))
    return Status::Error("--discovery_alpha must be in (0, 0.5)");
  if (!(FLAGS_rate_hz > 0.0 && FLAGS_rate_hz <= 1e5))
    return Status::Error("--rate_hz must be in (0, 1e5]");
  if (!(FLAGS_turn_s > 0.0 && FLAGS_turn_s <= 1000.0))
    return Status::Error("--turn_s must be in (0, 1000]");
  if (!(FLAGS_hold_s * FLAGS_rate_hz >= 2.0 && FLAGS_hold_s <= 1e4))
    return Status::Error("--hold_s must give at least 2 samples and be at most 1e4 s");
  if (FLAGS_poses < 10) return Status::Error("the discovery study needs --poses of at least 10");
  bool k2_given = false;
  TriadScaleNonlinearity k2{};
  options->truth = XsensLikeTriad();
  ACCELCAL_RETURN_IF_ERROR(ParseTruth(FLAGS_truth, &options->truth, &k2, &k2_given));
  if (k2_given || FLAGS_scale_nonlinearity || FLAGS_pose_set != "random")
    return Status::Error(
        "the discovery study simulates random holds and no scale_nonlinearity "
        "(--pose_set, --scale_nonlinearity and --truth=scale_nonlinearity_* are the sigma "
        "study's)");
  options->alpha = FLAGS_discovery_alpha;
  options->sessions = FLAGS_trials;
  options->seed = FLAGS_seed;
  options->poses = FLAGS_poses;
  options->hold_s = FLAGS_hold_s;
  options->turn_s = FLAGS_turn_s;
  options->rate_hz = FLAGS_rate_hz;
  options->gravity_mps2 = FLAGS_g;
  options->threads = FLAGS_threads;
  source->simulated = true;
  source->seed = FLAGS_seed;
  source->scenario =
      StringPrintf("triad sessions (%s truth, %d random holds of %g s)",
                   FLAGS_truth.empty() ? "Xsens-like" : "given", FLAGS_poses, FLAGS_hold_s);
  for (int k = 0; k < 3; ++k) {
    if (options->offset_drift[k] != 0.0)
      source->hidden.emplace_back(std::string("offset_drift_") + "xyz"[k],
                                  options -> offset_drift[k]);
  }
  return Status::Ok();
}

int RunDiscoveryStudy() {
  TriadDiscoveryStudyOptions options;
  TriadDiscoveryStudyResult result;
  DataSource source;
  ProgressStyle progress_style;
  Status status = DiscoveryOptionsFromFlags(&options, &source);
  if (status.ok()) status = ProgressStyleFromFlag(FLAGS_progress, &progress_style);
  if (status.ok()) status = CheckOutputPaths({{"--json", FLAGS_json}}, RunInputs());
  ProgressPrinter progress("triad_study", "sessions", progress_style, &std::cerr);
  options.progress = progress.Callback();
  if (status.ok()) status = RunTriadDiscoveryStudy(options, &result);
  std::string json_text;
  if (status.ok() && !FLAGS_json.empty())
    status = JsonText(WithProvenance(TriadDiscoveryStudyJson(options, result), source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("triad_study", status);
  std::cout << WithDataLine(source, TriadDiscoveryStudyText(options, result)) << std::flush;
  return 0;
}

int Run(int argc, char** argv) {
  if (!InitProblem("triad_study", kUsage, "problems/triad_study", &argc, &argv))
    return kExitBadInput;
  if (!gflags::GetCommandLineFlagInfoOrDie("discovery_alpha").is_default)
    return RunDiscoveryStudy();
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
