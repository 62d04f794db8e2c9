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
// Called from problems/calibrate_imu.cc when --log holds a comma, after its flags are parsed.

#include <gflags/gflags.h>

#include <iostream>
#include <set>
#include <sstream>

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

namespace accelcal {

// problems/calibrate_imu.cc, where the flags are defined.
Status TriadSessionOptionsFromFlags(TriadSessionOptions* options);
Status RefuseGyroscopeFlags(const std::string& where);

namespace {

// The sessions of --log, refused when fewer than 2, empty or repeated.
Status SplitSessions(std::vector<std::string>* paths) {
  std::stringstream list(FLAGS_log);
  std::string path;
  std::set<std::string> seen;
  while (std::getline(list, path, ',')) {
    if (path.empty()) {
      return Status::Error("--log='" + FLAGS_log +
                           "' holds an empty session; give the logs of one device as "
                           "--log=S1,S2,... with no empty item");
    }
    if (!seen.insert(path).second) {
      return Status::Error("--log names " + path +
                           " twice; each session of the device must be its own recording");
    }
    paths->push_back(path);
  }
  if (!FLAGS_log.empty() && FLAGS_log.back() == ',')
    return Status::Error("--log='" + FLAGS_log + "' ends with a comma: an empty session");
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
  return CheckOutputPaths({{"--json", FLAGS_json}}, RunInputs{paths, {}});
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
  for (size_t s = 0; s < paths.size(); ++s) files["session_" + std::to_string(s + 1)] = paths[s];
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
  ACCELCAL_RETURN_IF_ERROR(RefuseGyroscopeFlags("the sessions path (--log=S1,S2,...)"));
  if (!FLAGS_gyro_log.empty()) {
    return Status::Error(
        "--gyro_log names one gyroscope file; with several sessions give logs that hold the "
        "gyroscope's columns, or calibrate each session on its own");
  }
  std::vector<TriadLog> logs(paths.size());
  for (size_t s = 0; s < paths.size(); ++s) {
    ACCELCAL_RETURN_IF_ERROR(ReadImuLog(paths[s], read_options, &logs[s]));
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
    ACCELCAL_RETURN_IF_ERROR(CalibrateTriadSession(logs[s], options, &session.calibration)
                                 .WithContext("session " + std::to_string(s + 1) + " (" + paths[s] +
                                              ") fails calibration"));
    report->sessions.push_back(std::move(session));
  }
  std::vector<TriadMlResult> results;
  for (const TriadSessionReport& session : report->sessions)
    results.push_back(session.calibration.ml);
  return CombineTriadSessions(results, 0.95, &report->combined).WithContext("--log");
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
