// gyroscope_study: is the gyroscope's maximum-likelihood calibration's uncertainty honest
// (issue 32)? Simulates --trials hand-held sessions of one fixed design (poses, turns and their
// yaws drawn once from --seed) of an Xsens-like IMU, calibrates the accelerometer and then the
// gyroscope each time (estimation/gyroscope/gyroscope_ml_calibration.h), and compares per
// gyroscope unknown the spread of the estimates with the mean reported sigma, and the truth's
// coverage at 1, 2, 3 sigma. A design whose turns are all about one axis (--turn_set=planar) is
// refused, naming what it cannot determine and the axes to turn about.
//
//   build/bin/gyroscope_study --trials=1000 [--effects=g_sensitivity] --json=gyroscope_study.json

#include <gflags/gflags.h>

#include <iostream>

#include "common/format.h"
#include "io/json_file.h"
#include "problem_support.h"
#include "reporting/gyroscope_study_report.h"
#include "studies/gyroscope_monte_carlo.h"

// clang-format off
DEFINE_int32(trials, 1000, "Simulated sessions (Monte Carlo trials), 10 to 10^6; the verdict makes a claim only with at least 1000.");
DEFINE_uint64(seed, 1, "Seed: the design (directions, yaws) from its own stream, trial i's noise from (seed, i).");
DEFINE_string(turn_set, "random", "random: pose directions uniform on the sphere, turns of at least 40 degrees, each with a yaw about gravity uniform in +-90 degrees. planar: directions on the circle normal to x, no yaw, every turn about x: the accelerometer's poses lie in a plane and the study reports the refusal (poses spread enough for the accelerometer are always joined by turns about every axis).");
DEFINE_int32(poses, 30, "Poses per session, 3 to 1000 (poses - 1 turns).");
DEFINE_double(hold_s, 4.0, "Each pose's duration, s, in [0.5, 600].");
DEFINE_double(gyro_noise, 3.0, "The gyroscope's white noise per sample, counts, in (0, 1e4] (at the Xsens-like gain of 1/4770 (rad/s)/count, 3 counts is 6.3e-4 rad/s).");
DEFINE_string(effects, "", "Gyroscope effects to simulate AND estimate, comma-separated: g_sensitivity (G = 2e-4 (rad/s)/(m/s^2) on the diagonal, 1e-4 off it), scale_asymmetry (2e-3, -1e-3, 1.5e-3), scale_nonlinearity (1e-3, -2e-3, 1.5e-3 1/(rad/s)), time_offset (4e-3 s, the gyroscope lagging), and any effect a build registers, at the example values of its header (models/gyroscope_effects/). Empty: the 12 unknowns of the model.");
DEFINE_double(discovery, 0.0, "Also run the gyroscope's discovery at this alpha (e.g. 0.01) on every session and count its verdicts: with no --effects, the rate of any verdict but explained is its false-alarm rate (must be <= alpha + 2 sd); with --effects (then also estimated in the calibration), how often each is found. 0: no discovery.");
DEFINE_double(rate_hz, 100.0, "The sessions' sample rate, Hz, in [10, 10000] (the MIMU4444 array's 62.5).");
DEFINE_double(turn_abruptness, 0.0, "How abruptly each turn starts and stops, in [0, 1): the rate jumps to this fraction of its peak at the start and from it to 0 at the end, at a random time within a sample interval, as a hand that sets the sensor down against a table (docs/gyroscope.md, \"The turns' sampling error\"). 0: the smooth (1 - cos) turn.");
DEFINE_double(turn_sampling_alpha, 0.0, "The calibration estimates the turns' sampling error (kappa^2) when the turns reject the model without it at this level, in [0, 1]; 1: whenever they scatter beyond it; 0: never (discovery estimates it at alpha/4 whatever this says).");
DEFINE_bool(earth_rate, false, "Simulate the Earth's rate (7.292e-5 rad/s) at --latitude_deg in the gyroscope (vertical part about up, horizontal part at a random azimuth in each pose), and count it in the fit.");
DEFINE_double(latitude_deg, 59.35, "With --earth_rate: the latitude simulated, degrees north in [-90, 90].");
DEFINE_bool(latitude_known, false, "With --earth_rate: the fit is told the latitude (calibrate_imu --latitude_deg) and holds the vertical part; else it estimates it with its prior.");
DEFINE_string(json, "", "Write the results as JSON to this file (atomically).");
ACCELCAL_DEFINE_THREADS_FLAG(0);
ACCELCAL_DEFINE_PROGRESS_FLAG();
// clang-format on
ACCELCAL_FLAG_RANGE(trials, 10, 1000000);
ACCELCAL_FLAG_RANGE(poses, 3, 1000);
ACCELCAL_FLAG_RANGE(hold_s, 0.5, 600.0);
ACCELCAL_FLAG_OPEN_RANGE(gyro_noise, 0.0, 10000.0);
ACCELCAL_FLAG_RANGE(discovery, 0.0, 0.5);
ACCELCAL_FLAG_RANGE(rate_hz, 10.0, 10000.0);
ACCELCAL_FLAG_RANGE(turn_abruptness, 0.0, 0.99);
ACCELCAL_FLAG_RANGE(turn_sampling_alpha, 0.0, 1.0);
ACCELCAL_FLAG_RANGE(latitude_deg, -90.0, 90.0);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Checks the gyroscope's maximum-likelihood calibration's reported sigma against the spread of\n"
    "its estimates over simulated hand-held sessions (Monte Carlo), and the truth's coverage at\n"
    "1, 2, 3 sigma. Units: angles rad, gains (rad/s)/count, offsets and noise counts, hold s.\n"
    "Exit status: 0 on success (also when the verdict is FAIL: it is a measurement), 2 on bad\n"
    "input (one line on stderr; nothing is written).\n\n"
    "  gyroscope_study [--trials=1000] [--turn_set=random|planar] [--poses=30] [--hold_s=4]\n"
    "                  [--gyro_noise=3] [--effects=g_sensitivity,...] [--seed=1] [--json=FILE]";

// The example values --effects simulates.
Status EffectsFromFlag(GyroscopeMonteCarloOptions* options) {
  if (FLAGS_effects.empty()) return Status::Ok();
  size_t start = 0;
  while (start <= FLAGS_effects.size()) {
    const size_t comma = FLAGS_effects.find(',', start);
    const std::string name =
        FLAGS_effects.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const int effect = GyroscopeEffectIndex(name);
    if (effect < 0 || GyroscopeEffectInfos()[effect].not_a_candidate != nullptr) {
      std::vector<std::string> known;
      for (const GyroscopeEffectInfo& info : GyroscopeEffectInfos())
        if (info.not_a_candidate == nullptr) known.push_back(info.name);
      if (effect >= 0 && name == "earth_rate") {
        return Status::Error(
            "--effects: earth_rate is not an effect of the sensor (the fit holds it in every "
            "model); simulate it with --earth_rate and --latitude_deg");
      }
      if (effect >= 0) {
        return Status::Error("--effects: " + name + " is not one of discovery's candidates: " +
                             GyroscopeEffectInfos()[effect].not_a_candidate);
      }
      return Status::Error("--effects: unknown effect '" + name.substr(0, 40) +
                           "' (known: " + JoinStrings(known) + ")");
    }
    // The effect's example values (models/gyroscope_effects/), estimated.
    const GyroscopeEffectInfo& info = GyroscopeEffectInfos()[effect];
    const int first = GyroscopeEffectFirst(effect);
    for (int i = 0; i < info.coefficients; ++i) {
      options->design.effects[first + i] = info.example[i];
      options->estimated.push_back(first + i);
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return Status::Ok();
}

Status OptionsFromFlags(GyroscopeMonteCarloOptions* options, DataSource* source) {
  ACCELCAL_RETURN_IF_ERROR(
      ParseGyroscopeTurnSet(FLAGS_turn_set, &options->design.turn_set).WithContext("--turn_set"));
  ACCELCAL_RETURN_IF_ERROR(EffectsFromFlag(options));
  options->trials = FLAGS_trials;
  options->seed = FLAGS_seed;
  options->threads = FLAGS_threads;
  options->discovery_alpha = FLAGS_discovery;
  options->design.poses = FLAGS_poses;
  options->design.hold_s = FLAGS_hold_s;
  options->design.gyroscope_noise = {FLAGS_gyro_noise, FLAGS_gyro_noise, FLAGS_gyro_noise};
  options->design.rate_hz = FLAGS_rate_hz;
  options->design.turn_abruptness = FLAGS_turn_abruptness;
  options->design.turn_sampling_alpha = FLAGS_turn_sampling_alpha;
  options->design.earth_rate = FLAGS_earth_rate;
  options->design.latitude_deg = FLAGS_latitude_deg;
  options->design.latitude_known = FLAGS_latitude_known;
  source->simulated = true;
  source->seed = FLAGS_seed;
  source->scenario = StringPrintf(
      "hand-held IMU sessions (Xsens-like accelerometer and gyroscope, %s turns, %d poses of "
      "%g s at %g Hz%s%s%s)",
      FLAGS_turn_set.c_str(), FLAGS_poses, FLAGS_hold_s, FLAGS_rate_hz,
      FLAGS_turn_abruptness > 0.0
          ? StringPrintf(", turns abrupt at %g of their peak rate", FLAGS_turn_abruptness).c_str()
          : "",
      FLAGS_effects.empty() ? "" : ", effects ", FLAGS_effects.c_str());
  if (FLAGS_earth_rate) {
    source->scenario +=
        StringPrintf(", the Earth's rate at %g deg (%s to the fit)", FLAGS_latitude_deg,
                     FLAGS_latitude_known ? "given" : "not given");
  }
  return Status::Ok();
}

int Run(int argc, char** argv) {
  if (!InitProblem("gyroscope_study", kUsage, "problems/gyroscope_study", &argc, &argv))
    return kExitBadInput;
  GyroscopeStudyReport report;
  DataSource source;
  ProgressStyle progress_style;
  Status status = OptionsFromFlags(&report.options, &source);
  if (status.ok()) status = ProgressStyleFromFlag(FLAGS_progress, &progress_style);
  if (status.ok()) status = CheckOutputPaths({{"--json", FLAGS_json}}, RunInputs());
  ProgressPrinter progress("gyroscope_study", "trials", progress_style, &std::cerr);
  report.options.progress = progress.Callback();
  if (status.ok()) status = RunGyroscopeMonteCarlo(report.options, &report.result);
  std::string json_text;
  if (status.ok() && !FLAGS_json.empty())
    status = JsonText(WithProvenance(GyroscopeStudyJson(report), source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("gyroscope_study", status);
  std::cout << WithDataLine(source, GyroscopeStudyText(report)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("gyroscope_study", accelcal::Run, argc, argv);
}
