// triad_repeatability: how much do an array's triads move between sessions, and does the
// new-session sigma cover a session it has not seen? Every device of every session is
// calibrated on its own (the single-session `calibrate_imu --mode=ml`), then per parameter:
// each device's between-session sigma tau (random effects, estimation/triad/triad_sessions.h), the
// array's two-way split into a shift common to all devices and each device's own, and a
// leave-one-session-out check of three ways to predict a session (device, pooled, array;
// studies/triad_repeatability.h), with coverage per parameter kind. Then (--trials > 0) the
// same three schemes on simulated arrays with known between-session sigmas (Monte Carlo).
//
// Input: a folder of sessions (--data_dir), each a subfolder (run1, run2, ...) holding one
// log per device (imu1.csv ...), the layout of ../shared/data/mimu4444. Logs with a gyroscope
// (--log_suffix=_acc_gyr: imu1_acc_gyr.csv ...) have it calibrated too, each session as
// calibrate_imu --mode=ml does (estimation/gyroscope/gyroscope_sessions.h), its 12 unknowns
// combined per device and checked by leaving one session out as the accelerometer's.
//
//   build/bin/triad_repeatability --data_dir=../shared/data/mimu4444 --g=9.8187 \
//       --trials=500 --json=repeatability.json
//   build/bin/triad_repeatability --data_dir=../shared/data/mimu4444 --log_suffix=_acc_gyr \
//       --initial_gyro_gain=0.00106422515 --trials=0

#include "studies/triad_repeatability.h"

#include <gflags/gflags.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "estimation/gyroscope/gyroscope_sessions.h"
#include "estimation/triad/triad_sessions.h"
#include "io/imu_log.h"
#include "io/json_file.h"
#include "io/output_paths.h"
#include "io/provenance.h"
#include "problem_support.h"
#include "reporting/triad_sessions_report.h"
#include "studies/gyroscope_repeatability.h"

// clang-format off
DEFINE_string(data_dir, "", "The sessions: a folder whose subfolders (e.g. run1, run2, run3; every one whose name starts with --session_prefix) each hold one log per device (imu1.csv ... imuD.csv, CSV with header t_s,acc_x,acc_y,acc_z), as ../shared/data/mimu4444.");
DEFINE_string(session_prefix, "run", "Subfolders of --data_dir whose name starts with this are sessions, in natural order (run2 before run10).");
DEFINE_string(device_prefix, "imu", "The logs <device_prefix><k><log_suffix>.csv, k = 1, 2, ... in each session: the devices.");
DEFINE_string(log_suffix, "", "What follows the device's number in its log's name: empty for imu1.csv; _acc_gyr for mimu4444's logs with the gyroscope's columns (imu1_acc_gyr.csv), whose gyroscope is then calibrated too.");
DEFINE_string(gyro_unit, "count", "Logs with a gyroscope: the unit of its outputs, count, rad/s or deg/s.");
DEFINE_double(initial_gyro_gain, 0.0, "Logs with a gyroscope: its gain to start from, (rad/s) per unit of output (mimu4444: 1/16.4 deg/s per count = 0.00106422515). 0: the unit's nominal gain; counts have none, and their gyroscope is then not calibrated (said per log).");
DEFINE_double(g, 9.8187, "Local gravity, m/s^2 (mimu4444: Stockholm, about 9.8187). Earth's surface gravity is 9.76 to 9.84 m/s^2, so 9.7 to 9.9 is accepted: the flag is in m/s^2, not in g, and a wrong g scales every gain by g_stated / g_true, which static poses cannot detect.");
DEFINE_string(unit, "count", "The logs' unit: count, m/s^2 or g.");
DEFINE_int32(trials, 500, "Monte Carlo arrays simulated after the measured check (0: none), 0 to 100000.");
DEFINE_int32(mc_devices, 8, "Monte Carlo: devices per simulated array, 2 to 64.");
DEFINE_int32(mc_training_sessions, 2, "Monte Carlo: sessions the schemes learn from before predicting one more, 2 to 20 (2: as the leave-one-session-out check on 3 sessions).");
DEFINE_uint64(seed, 1, "Monte Carlo seed; array i uses the stream (seed, i).");
DEFINE_string(json, "", "Write the results as JSON to this file (atomically).");
// clang-format on
ACCELCAL_FLAG_RANGE(g, 9.7, 9.9);
ACCELCAL_FLAG_RANGE(trials, 0, 100000);
ACCELCAL_FLAG_RANGE(mc_devices, 2, 64);
ACCELCAL_FLAG_RANGE(mc_training_sessions, 2, 20);
ACCELCAL_FLAG_RANGE(initial_gyro_gain, 0.0, 100.0);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Between-session repeatability of an array's triads: per device, session and parameter the\n"
    "estimate and its within-session sigma; per parameter the between-session sigma; a\n"
    "leave-one-session-out check of the new-session sigma (coverage per parameter kind); and a\n"
    "Monte Carlo check of the same on simulated arrays. Units: angles rad, gains\n"
    "(m/s^2)/count, offsets counts (and mm/s^2).\n"
    "Exit status: 0 on success, 2 on bad input (one line on stderr; nothing is written).\n\n"
    "  triad_repeatability --data_dir=../shared/data/mimu4444 [--g=9.8187] [--trials=500]\n"
    "                      [--json=FILE]";

// The number in a name after its prefix (run12 -> 12), or -1.
long NumberAfter(const std::string& name, const std::string& prefix) {
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return -1;
  const std::string digits = name.substr(prefix.size());
  if (!std::all_of(digits.begin(), digits.end(), ::isdigit) || digits.size() > 6) return -1;
  return std::stol(digits);
}

Status FindSessions(std::vector<std::string>* sessions, std::vector<std::string>* devices) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(FLAGS_data_dir, error)) {
    return Status::Error("--data_dir='" + FLAGS_data_dir +
                         "' is not a folder; give the folder of the sessions (run1, run2, ...)");
  }
  std::vector<std::pair<long, std::string>> found;
  for (const fs::directory_entry& entry : fs::directory_iterator(FLAGS_data_dir, error)) {
    const std::string name = entry.path().filename().string();
    const long number = NumberAfter(name, FLAGS_session_prefix);
    if (number >= 0 && entry.is_directory()) found.emplace_back(number, name);
  }
  std::sort(found.begin(), found.end());
  for (const auto& session : found) sessions->push_back(session.second);
  if (sessions->size() < 3) {
    return Status::Error(FLAGS_data_dir + " holds " + std::to_string(sessions->size()) +
                         " session folder(s) named " + FLAGS_session_prefix +
                         "<n>; leaving one out needs at least 3");
  }
  for (int k = 1;; ++k) {
    const std::string name = FLAGS_device_prefix + std::to_string(k);
    if (!fs::is_regular_file(
            fs::path(FLAGS_data_dir) / sessions->front() / (name + FLAGS_log_suffix + ".csv"),
            error))
      break;
    devices->push_back(name);
  }
  if (devices->size() < 2) {
    return Status::Error(FLAGS_data_dir + "/" + sessions->front() + " holds fewer than 2 logs " +
                         FLAGS_device_prefix + "1" + FLAGS_log_suffix + ".csv, " +
                         FLAGS_device_prefix + "2" + FLAGS_log_suffix +
                         ".csv, ...; the array study needs at least 2 devices");
  }
  return Status::Ok();
}

// Each device's gyroscope sessions combined (those calibrated), and the leave-one-session-out
// check over the devices whose every session's gyroscope calibrated.
Status GyroscopeRepeatability(TriadRepeatabilityReport* report) {
  std::vector<std::vector<GyroscopeMlResult>> calibrated;
  for (size_t d = 0; d < report->device_names.size(); ++d) {
    report->gyroscope_per_device.emplace_back();
    ACCELCAL_RETURN_IF_ERROR(CombineGyroscopeSessionOutcomes(report->gyroscope_sessions[d], 0.95,
                                                             0.05,
                                                             &report->gyroscope_per_device.back())
                                 .WithContext(report->device_names[d]));
    if (report->gyroscope_per_device.back().sessions.size() != report->session_names.size())
      continue;
    report->gyroscope_devices.push_back(static_cast<int>(d));
    calibrated.emplace_back();
    for (const GyroscopeSessionOutcome& outcome : report->gyroscope_sessions[d])
      calibrated.back().push_back(outcome.calibration.ml);
  }
  if (calibrated.size() < 2) {
    report->gyroscope_loso_not_run =
        StringPrintf("%zu device(s) with every session's gyroscope calibrated; the check needs 2",
                     calibrated.size());
    return Status::Ok();
  }
  report->has_gyroscope_loso = true;
  return LeaveOneSessionOutOf(GyroscopeArrayEstimates(calibrated), GyroscopeParameterKinds(),
                              &report->gyroscope_loso)
      .WithContext("the gyroscope");
}

Status LoadAndCalibrate(TriadRepeatabilityReport* report, DataSource* source) {
  ACCELCAL_RETURN_IF_ERROR(FindSessions(&report->session_names, &report->device_names));
  report->gravity_mps2 = FLAGS_g;
  TriadSessionOptions options;
  options.gravity_mps2 = FLAGS_g;
  ACCELCAL_RETURN_IF_ERROR(ParseTriadOutputUnit(FLAGS_unit, &options.unit).WithContext("--unit"));
  std::map<std::string, std::string> files;
  for (const std::string& session : report->session_names) {
    for (const std::string& device : report->device_names) {
      files[session + "/" + device] =
          (std::filesystem::path(FLAGS_data_dir) / session / (device + FLAGS_log_suffix + ".csv"))
              .string();
    }
  }
  ACCELCAL_RETURN_IF_ERROR(DescribeMeasuredData(FLAGS_data_dir, files, source));
  // A session copied (or a folder linked) under two names would be two sessions that agree
  // exactly, and the between-session spread would come out too small.
  std::map<std::string, std::string> by_content;
  for (const auto& [key, path] : files) {
    const std::string& sha256 = source->files.at(key).sha256;
    if (!by_content.emplace(sha256, path).second) {
      return Status::Error(path + " holds the same bytes as " + by_content[sha256] + " (SHA-256 " +
                           sha256.substr(0, 12) +
                           "...); each log must be its own recording of its own device");
    }
  }
  report->sessions.assign(report->device_names.size(), {});
  report->gyroscope_sessions.assign(report->device_names.size(), {});
  GyroscopeSessionsOptions gyroscope;
  gyroscope.session.gravity_mps2 = FLAGS_g;
  ACCELCAL_RETURN_IF_ERROR(ParseGyroscopeOutputUnit(FLAGS_gyro_unit, &gyroscope.session.unit)
                               .WithContext("--gyro_unit"));
  gyroscope.initial_gain = FLAGS_initial_gyro_gain;
  report->gyroscope_unit = gyroscope.session.unit;
  for (const std::string& session : report->session_names) {
    for (size_t d = 0; d < report->device_names.size(); ++d) {
      const std::string& path = files.at(session + "/" + report->device_names[d]);
      TriadLog log;
      ACCELCAL_RETURN_IF_ERROR(ReadImuLog(path, &log));
      TriadSessionCalibration calibration;
      ACCELCAL_RETURN_IF_ERROR(CalibrateTriadSession(log, options, &calibration)
                                   .WithContext(path + " fails calibration"));
      report->sessions[d].push_back(calibration.ml);
      report->has_gyroscope = report->has_gyroscope || log.has_gyroscope();
      report->gyroscope_sessions[d].push_back(
          CalibrateSessionGyroscope(log, calibration, gyroscope));
    }
  }
  if (!report->has_gyroscope && FLAGS_initial_gyro_gain > 0.0) {
    return Status::Error(
        "--initial_gyro_gain is for the gyroscope, and no log has one: give logs with the "
        "gyroscope's columns, e.g. --log_suffix=_acc_gyr for mimu4444's imu<k>_acc_gyr.csv");
  }
  for (const std::vector<TriadMlResult>& device : report->sessions) {
    report->per_device.emplace_back();
    ACCELCAL_RETURN_IF_ERROR(CombineTriadSessions(device, 0.95, &report->per_device.back()));
  }
  ACCELCAL_RETURN_IF_ERROR(ArrayVariances(report->sessions, &report->array));
  ACCELCAL_RETURN_IF_ERROR(LeaveOneSessionOut(report->sessions, &report->loso));
  return report->has_gyroscope ? GyroscopeRepeatability(report) : Status::Ok();
}

Status RunMonteCarlo(TriadRepeatabilityReport* report) {
  if (FLAGS_trials == 0) return Status::Ok();
  RepeatabilityMonteCarloOptions options = Mimu4444LikeMonteCarlo();
  options.trials = FLAGS_trials;
  options.devices = FLAGS_mc_devices;
  options.training_sessions = FLAGS_mc_training_sessions;
  options.gravity_mps2 = FLAGS_g;
  options.seed = FLAGS_seed;
  report->has_monte_carlo = true;
  return RunRepeatabilityMonteCarlo(options, &report->monte_carlo);
}

int Run(int argc, char** argv) {
  if (!InitProblem("triad_repeatability", kUsage, "problems/triad_repeatability", &argc, &argv))
    return kExitBadInput;
  TriadRepeatabilityReport report;
  DataSource source;
  std::string json_text;
  Status status = FLAGS_data_dir.empty()
                      ? Status::Error("--data_dir is required: the folder of the sessions")
                      : CheckOutputPaths({{"--json", FLAGS_json}}, RunInputs{{}, {FLAGS_data_dir}});
  if (status.ok()) status = LoadAndCalibrate(&report, &source);
  if (status.ok()) status = RunMonteCarlo(&report);
  if (status.ok() && !FLAGS_json.empty())
    status = JsonText(WithProvenance(TriadRepeatabilityJson(report), source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("triad_repeatability", status);
  std::cout << WithDataLine(source, TriadRepeatabilityTable(report)) << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("triad_repeatability", accelcal::Run, argc, argv);
}
