// calibrate_imu --log=S1,S2,... --mode=ml: several sessions of ONE device, each calibrated on
// its own by the single-session ml mode's sequence (estimation/triad/triad_session_calibration.h:
// noise-floor detector, maximum likelihood with ceres::Covariance), then combined per parameter
// by a random-effects model (estimation/triad/triad_sessions.h): the device's common value, the
// within-session sigma (`stddev`), the between-session sigma (tau) with its interval, and the
// sigma a NEW session's estimate scatters by about the common value (`stddev_new_session`), with
// the Student t multiplier its 95% interval needs with so few sessions. docs/repeatability.md.
//
//   build/bin/calibrate_imu --log=run1/imu1.csv,run2/imu1.csv,run3/imu1.csv --g=9.8187 \
//       --mode=ml --json=imu1_sessions.json
//
// With a gyroscope (the logs' gyroscope columns, or imu_tk's pairs: --gyro_log=G1,G2,..., one per
// session), each session's gyroscope is calibrated as the single-session ml mode calibrates it
// (estimation/gyroscope/gyroscope_session_calibration.h), its 12 unknowns combined by the same
// model (estimation/gyroscope/gyroscope_sessions.h); a session whose gyroscope is not calibrated
// says why and is left out of that combination. Each sensor's sessions are checked against each
// other (CheckSessionDrift): a session that drifts is named with its parameters.
//
//   build/bin/calibrate_imu --log=run1/imu1_acc_gyr.csv,run2/imu1_acc_gyr.csv,run3/imu1_acc_gyr.csv
//   \
//       --g=9.8187 --mode=ml --initial_gyro_gain=0.00106422515 --json=imu1_sessions.json
//
// Called from problems/calibrate_imu.cc when --log holds a comma, after its flags are parsed.

#include <gflags/gflags.h>

#include <cmath>
#include <iostream>
#include <set>
#include <sstream>

#include "estimation/gyroscope/gyroscope_sessions.h"
#include "estimation/triad/triad_session_calibration.h"
#include "estimation/triad/triad_sessions.h"
#include "io/imu_log.h"
#include "io/json_file.h"
#include "io/output_paths.h"
#include "io/provenance.h"
#include "problem_support.h"
#include "reporting/triad_sessions_report.h"

DECLARE_string(log);
DECLARE_string(mode);
DECLARE_string(detector);
DECLARE_string(session);
DECLARE_string(reference);
DECLARE_bool(scale_nonlinearity);
DECLARE_string(json);
DECLARE_string(report);
DECLARE_string(calibration_out);
DECLARE_string(columns);
DECLARE_double(rate_hz);
DECLARE_string(time_unit);
DECLARE_string(topic);
DECLARE_string(bag_time);
DECLARE_string(gyro_log);
DECLARE_string(gyro_unit);
DECLARE_double(initial_gyro_gain);
DECLARE_double(latitude_deg);
DECLARE_bool(gyro_turn_sampling);
DECLARE_string(gyro_bias);
DECLARE_string(imu_tk_calib_out);

namespace accelcal {

// problems/calibrate_imu.cc, where the flags are defined.
Status TriadSessionOptionsFromFlags(TriadSessionOptions* options);
Status ValidateGyroscopeFlags();

namespace {

// The drift check's level per sensor and session (CheckSessionDrift).
constexpr double kDriftLevel = 0.05;

bool FlagGiven(const char* name) { return !gflags::GetCommandLineFlagInfoOrDie(name).is_default; }

// The items of a comma-separated list flag (--log, --gyro_log), refused when empty or repeated.
Status SplitList(const std::string& flag, const std::string& value,
                 std::vector<std::string>* paths) {
  std::stringstream list(value);
  std::string path;
  std::set<std::string> seen;
  while (std::getline(list, path, ',')) {
    if (path.empty()) {
      return Status::Error(flag + "='" + value +
                           "' holds an empty session; give the logs of one device as " + flag +
                           "=S1,S2,... with no empty item");
    }
    if (!seen.insert(path).second) {
      return Status::Error(flag + " names " + path +
                           " twice; each session of the device must be its own recording");
    }
    paths->push_back(path);
  }
  if (!value.empty() && value.back() == ',')
    return Status::Error(flag + "='" + value + "' ends with a comma: an empty session");
  return Status::Ok();
}

// The sessions of --log, refused when fewer than 2, empty or repeated.
Status SplitSessions(std::vector<std::string>* paths) {
  ACCELCAL_RETURN_IF_ERROR(SplitList("--log", FLAGS_log, paths));
  if (paths->size() < 2) {
    return Status::Error("--log='" + FLAGS_log +
                         "' names fewer than 2 sessions; a between-session sigma needs at least "
                         "2 (give one log without a comma for a single session)");
  }
  return Status::Ok();
}

Status ValidateSessionFlags(const std::vector<std::string>& paths) {
  if (FLAGS_mode != "ml") {
    return Status::Error(
        "--log with several sessions (a comma) needs --mode=ml: only the ml "
        "mode gives each session's covariance; got --mode=" +
        FLAGS_mode);
  }
  if (FLAGS_detector != "noise_floor") {
    return Status::Error(
        "--log with several sessions uses --detector=noise_floor only "
        "(imu_tk's needs an initial rest per log); drop --detector");
  }
  if (FLAGS_scale_nonlinearity || !FLAGS_report.empty() || !FLAGS_calibration_out.empty() ||
      !FLAGS_session.empty() || !FLAGS_reference.empty()) {
    return Status::Error(
        "--log with several sessions writes --json only: --scale_nonlinearity, "
        "--report, --calibration_out, --session and --reference belong to a "
        "single session");
  }
  // --unit, --initial_offset and --window as the single-session mode reads them; the
  // detector refuses an even window itself.
  TriadSessionOptions options;
  ACCELCAL_RETURN_IF_ERROR(TriadSessionOptionsFromFlags(&options));
  // The gyroscope's flags as the single-session ml mode reads them; imu_tk's are refused.
  ACCELCAL_RETURN_IF_ERROR(ValidateGyroscopeFlags());
  for (const char* name : {"gyro_bias", "imu_tk_calib_out"}) {
    if (FlagGiven(name)) {
      return Status::Error(std::string("--") + name +
                           " belongs to --mode=imu_tk; the sessions path (--log=S1,S2,...) does "
                           "not read it");
    }
  }
  std::vector<std::string> inputs = paths;
  if (!FLAGS_gyro_log.empty()) {
    std::vector<std::string> gyroscope_paths;
    ACCELCAL_RETURN_IF_ERROR(SplitList("--gyro_log", FLAGS_gyro_log, &gyroscope_paths));
    if (gyroscope_paths.size() != paths.size()) {
      return Status::Error(StringPrintf(
          "--gyro_log names %zu gyroscope file(s) for %zu sessions; give one per session of "
          "--log, in its order (imu_tk's pairs)",
          gyroscope_paths.size(), paths.size()));
    }
    inputs.insert(inputs.end(), gyroscope_paths.begin(), gyroscope_paths.end());
  }
  return CheckOutputPaths({{"--json", FLAGS_json}}, RunInputs{inputs, {}});
}

// --gyro_log's files, one per session (ValidateSessionFlags checked the list), or empty strings
// without it.
std::vector<std::string> GyroscopePaths(size_t sessions) {
  std::vector<std::string> paths;
  if (!FLAGS_gyro_log.empty() && !SplitList("--gyro_log", FLAGS_gyro_log, &paths).ok())
    paths.clear();
  paths.resize(sessions);
  return paths;
}

// The gyroscope's unit in a session: --gyro_unit, or what the log's columns state when it was not
// given (the single-session mode's rule, TakeStatedUnitOf).
Status SessionGyroscopeUnit(const ImuLogSource& source, std::string* unit) {
  *unit = FLAGS_gyro_unit;
  std::vector<std::string> notes;
  return TakeStatedUnitOf(source.gyroscope_unit, {"count", "rad/s", "deg/s"}, "gyro_unit",
                          "gyroscope outputs", "gyroscope", unit, &notes, source.units_stated_by);
}

// Every session's gyroscope (when some log has one), then their combination.
Status CalibrateGyroscopes(const std::vector<TriadLog>& logs, const std::string& unit,
                           TriadSessionsReport* report) {
  GyroscopeSessionsOptions& options = report->gyroscope_options;
  options.session.gravity_mps2 = report->options.gravity_mps2;
  ACCELCAL_RETURN_IF_ERROR(
      ParseGyroscopeOutputUnit(unit, &options.session.unit).WithContext("--gyro_unit"));
  options.initial_gain = FlagGiven("initial_gyro_gain") ? FLAGS_initial_gyro_gain : 0.0;
  options.session.turn_sampling = FLAGS_gyro_turn_sampling;
  options.session.latitude_given = FlagGiven("latitude_deg");
  options.session.latitude_rad = FLAGS_latitude_deg * M_PI / 180.0;
  options.session.alpha = report->options.alpha;
  std::vector<GyroscopeSessionOutcome> outcomes;
  for (size_t s = 0; s < logs.size(); ++s) {
    TriadSessionReport& session = report->sessions[s];
    session.gyroscope = CalibrateSessionGyroscope(logs[s], session.calibration, options);
    outcomes.push_back(session.gyroscope);
  }
  return CombineGyroscopeSessionOutcomes(outcomes, 0.95, kDriftLevel, &report->gyroscope);
}

// The unit a log's outputs look like (the first of count, m/s^2, g its outputs match), to
// refuse sessions recorded in different units before any is calibrated.
const char* ApparentUnit(const TriadLog& log) {
  for (TriadOutputUnit unit :
       {TriadOutputUnit::kCount, TriadOutputUnit::kMps2, TriadOutputUnit::kG}) {
    double offset = 0.0;
    if (TriadStartOffset(log, unit, TriadOffsetStart(), &offset).ok())
      return TriadOutputUnitName(unit);
  }
  return "none of count, m/s^2, g";
}

Status LoadAndCalibrate(const std::vector<std::string>& paths, TriadSessionsReport* report,
                        DataSource* source) {
  std::map<std::string, std::string> files;
  const std::vector<std::string> gyroscope_files = GyroscopePaths(paths.size());
  for (size_t s = 0; s < paths.size(); ++s) {
    files["session_" + std::to_string(s + 1)] = paths[s];
    if (!gyroscope_files[s].empty())
      files["session_" + std::to_string(s + 1) + "_gyroscope"] = gyroscope_files[s];
  }
  ACCELCAL_RETURN_IF_ERROR(DescribeMeasuredData("", files, source));
  std::map<std::string, std::string> by_content;
  for (size_t s = 0; s < paths.size(); ++s) {
    const std::string& sha256 = source->files.at("session_" + std::to_string(s + 1)).sha256;
    if (!by_content.emplace(sha256, paths[s]).second) {
      return Status::Error(paths[s] + " holds the same bytes as " + by_content[sha256] +
                           " (SHA-256 " + sha256.substr(0, 12) +
                           "...); each session must be its own recording");
    }
  }
  TriadSessionOptions& options = report->options;
  ACCELCAL_RETURN_IF_ERROR(TriadSessionOptionsFromFlags(&options));
  ImuLogReadOptions read_options;
  ACCELCAL_RETURN_IF_ERROR(ACCELCAL_IMU_LOG_OPTIONS(&read_options));
  const std::vector<std::string> gyroscope_paths = GyroscopePaths(paths.size());
  std::vector<TriadLog> logs(paths.size());
  std::string gyroscope_unit;  // the first session's with a gyroscope
  for (size_t s = 0; s < paths.size(); ++s) {
    read_options.gyroscope_path = gyroscope_paths[s];
    ImuLogSource log_source;
    ACCELCAL_RETURN_IF_ERROR(
        ReadImuLog(paths[s], read_options, &logs[s], ImuLogSpacing::kEven, &log_source));
    if (logs[s].has_gyroscope()) {
      std::string unit;
      ACCELCAL_RETURN_IF_ERROR(
          SessionGyroscopeUnit(log_source, &unit)
              .WithContext(gyroscope_paths[s].empty() ? paths[s] : gyroscope_paths[s]));
      if (!gyroscope_unit.empty() && unit != gyroscope_unit) {
        return Status::Error("the sessions' gyroscopes hold different units: " + paths[s] +
                             "'s is in " + unit + ", an earlier session's in " + gyroscope_unit +
                             "; combine sessions of one device in one unit");
      }
      gyroscope_unit = unit;
    }
    const std::string unit = ApparentUnit(logs[s]);
    const std::string first = ApparentUnit(logs[0]);
    if (unit != first) {
      return Status::Error("the sessions hold different units: " + paths[0] + " looks like " +
                           first + ", " + paths[s] + " like " + unit +
                           "; combine sessions of one device in one unit");
    }
  }
  for (size_t s = 0; s < paths.size(); ++s) {
    TriadSessionReport session;
    session.path = paths[s];
    session.sha256 = source->files.at("session_" + std::to_string(s + 1)).sha256;
    session.gyroscope_path = gyroscope_paths[s];
    if (!session.gyroscope_path.empty())
      session.gyroscope_sha256 =
          source->files.at("session_" + std::to_string(s + 1) + "_gyroscope").sha256;
    ACCELCAL_RETURN_IF_ERROR(CalibrateTriadSession(logs[s], options, &session.calibration)
                                 .WithContext("session " + std::to_string(s + 1) + " (" + paths[s] +
                                              ") fails calibration"));
    report->sessions.push_back(std::move(session));
  }
  std::vector<TriadMlResult> results;
  for (const TriadSessionReport& session : report->sessions)
    results.push_back(session.calibration.ml);
  ACCELCAL_RETURN_IF_ERROR(
      CombineTriadSessions(results, 0.95, &report->combined).WithContext("--log"));
  ACCELCAL_RETURN_IF_ERROR(
      CheckSessionDrift(TriadSessionEstimates(results), kDriftLevel, &report->drift));
  report->has_gyroscope = !gyroscope_unit.empty();
  if (!report->has_gyroscope) {
    for (const char* name :
         {"gyro_unit", "initial_gyro_gain", "latitude_deg", "gyro_turn_sampling"}) {
      if (FlagGiven(name)) {
        return Status::Error("--" + std::string(name) +
                             " is for the gyroscope, and no session's log has one: give logs "
                             "with gyroscope columns (gx, gy, gz; docs/log-layouts.md), or "
                             "imu_tk's gyroscope files with --gyro_log=G1,G2,...");
      }
    }
    return Status::Ok();
  }
  return CalibrateGyroscopes(logs, gyroscope_unit, report);
}

}  // namespace

int RunCalibrateImuSessions() {
  std::vector<std::string> paths;
  TriadSessionsReport report;
  DataSource source;
  std::string json_text;
  Status status = SplitSessions(&paths);
  if (status.ok()) status = ValidateSessionFlags(paths);
  if (status.ok()) status = LoadAndCalibrate(paths, &report, &source);
  if (status.ok() && !FLAGS_json.empty())
    status = JsonText(WithProvenance(TriadSessionsJson(report), source), &json_text);
  if (status.ok()) status = WriteOutputFiles({{FLAGS_json, json_text}});
  if (!status.ok()) return ExitWithError("calibrate_imu", status);
  std::cout << WithDataLine(source, TriadSessionsTable(report)) << std::flush;
  return 0;
}

}  // namespace accelcal
