#include "reporting/calibrate_imu_run.h"

#include <utility>
#include <vector>

#include "common/format.h"
#include "estimation/gyroscope/gyroscope_discovery.h"
#include "estimation/gyroscope/gyroscope_session_calibration.h"
#include "estimation/gyroscope/imu_tk_gyroscope_calibration.h"
#include "estimation/triad/imu_tk_calibration.h"

namespace accelcal {
namespace {

std::string WithoutPrefix(const std::string& text, const std::string& prefix) {
  return text.rfind(prefix, 0) == 0 ? text.substr(prefix.size()) : text;
}

// The gyroscope's file in messages: its own, else the log's.
const std::string& GyroscopeWhere(const CalibrateImuOptions& options) {
  return options.gyroscope_log_name.empty() ? options.log_name : options.gyroscope_log_name;
}

// imu_tk's start: angles 0, gains 1 per unit of output (9.80665 for g), the offsets of
// TriadStartOffset (the unit checked against the log with them).
Status InitialGuess(const TriadLog& log, const CalibrateImuOptions& options,
                    CalibrateImuReport* report) {
  const TriadSessionOptions& session = options.session;
  double offset = 0.0;
  ACCELCAL_RETURN_IF_ERROR(
      TriadStartOffset(log, session.unit, session.offset, &offset).WithContext(options.log_name));
  report->initial_offset_from = "--initial_offset";
  if (session.offset.automatic && session.unit != TriadOutputUnit::kCount) {
    report->initial_offset_from = "auto: 0 for a physical unit";
  } else if (session.offset.automatic) {
    report->initial_offset_from = offset > 0.0 ? "auto: the mid-scale of an unsigned ADC's range"
                                               : "auto: 0, the mid-scale of a signed ADC";
  }
  TriadParameters& initial = report->options.initial;
  initial = TriadParametersWithOffset(offset, offset, offset);
  if (session.unit == TriadOutputUnit::kG) {
    for (int k = 0; k < 3; ++k) initial[kTriadGainX + k] = 9.80665;
  }
  return Status::Ok();
}

Status SolveImuTk(const TriadLog& log, const CalibrateImuOptions& options,
                  CalibrateImuReport* report) {
  ImuTkOptions& imu_tk = report->options;  // imu_tk.initial: set by InitialGuess
  imu_tk.gravity_mps2 = options.session.gravity_mps2;
  imu_tk.init_rest_s = options.init_rest_s;
  imu_tk.window_samples = options.imu_tk_window_samples;
  imu_tk.interval_samples = options.interval_samples;
  imu_tk.min_intervals = options.min_intervals;
  ACCELCAL_RETURN_IF_ERROR(
      CalibrateImuTk(log, imu_tk, &report->result).WithContext(options.log_name));
  ACCELCAL_RETURN_IF_ERROR(CheckGainsMatchUnit(report->result.best().parameters, report->unit)
                               .WithContext(options.log_name));
  report->rest_end_s = log.timestamp_s[report->result.rest_end];
  return Status::Ok();
}

std::vector<StaticInterval> UsedImuTkIntervals(const ImuTkResult& result) {
  std::vector<StaticInterval> used;
  for (size_t i = 0; i < result.intervals.size(); ++i) {
    if (result.interval_used[i]) used.push_back(result.intervals[i]);
  }
  return used;
}

Status SolveMl(const TriadLog& log, const CalibrateImuOptions& options,
               CalibrateImuReport* report) {
  report->detector = options.detector;
  report->imu_tk_status = SolveImuTk(log, options, report);
  TriadSessionCalibration session;
  if (options.detector == "imu_tk") {
    ACCELCAL_RETURN_IF_ERROR(report->imu_tk_status);
    ACCELCAL_RETURN_IF_ERROR(CalibrateTriadSessionOnIntervals(
                                 log, UsedImuTkIntervals(report->result), options.session, &session)
                                 .WithContext(options.log_name));
  } else {
    report->noise_floor_options = options.session.detector;
    const std::vector<StaticInterval> imu_tk_intervals = report->imu_tk_status.ok()
                                                             ? UsedImuTkIntervals(report->result)
                                                             : std::vector<StaticInterval>();
    ACCELCAL_RETURN_IF_ERROR(
        CalibrateTriadSessionWithFallback(
            log, options.session, report->imu_tk_status.ok() ? &imu_tk_intervals : nullptr,
            WithoutPrefix(report->imu_tk_status.message(), options.log_name + ": "), &session,
            &report->detector_fallback_reason)
            .WithContext(options.log_name));
    if (!report->detector_fallback_reason.empty()) report->detector = "imu_tk";
  }
  TakeSessionCalibration(std::move(session), report);
  return Status::Ok();
}

// The note "gyroscope: read (N samples)" the reader's caller added, or a new one, ending with
// why the gyroscope was not calibrated.
void NoteGyroscopeNotCalibrated(const TriadLog& log, const std::string& why,
                                CalibrateImuReport* report) {
  for (std::string& note : report->log_notes) {
    if (note.rfind("gyroscope: read (", 0) != 0) continue;
    note = note.substr(0, note.find(';')) + "; not calibrated: " + why;
    return;
  }
  report->log_notes.push_back("gyroscope: read (" + std::to_string(log.gyroscope.size()) +
                              " samples); not calibrated: " + why);
}

// The unit and the start of the gyroscope's gains; *calibrate false when the gyroscope is
// left (counts, nothing said of it).
Status GyroscopeStart(const TriadLog& log, const CalibrateImuOptions& options,
                      CalibrateImuReport* report, bool* calibrate) {
  *calibrate = true;
  report->gyroscope_unit = options.gyroscope_unit;
  double gain = options.initial_gyro_gain;
  report->initial_gyro_gain_from = "--initial_gyro_gain";
  if (!(gain > 0.0)) {
    gain = GyroscopeNominalGain(report->gyroscope_unit);
    if (report->gyroscope_unit == GyroscopeOutputUnit::kCount && !options.gyroscope_asked) {
      *calibrate = false;
      NoteGyroscopeNotCalibrated(
          log,
          "its outputs are counts and its calibration needs their gain to start from; give "
          "--initial_gyro_gain=G in (rad/s) per count (G = 1/S for a datasheet sensitivity S "
          "in counts per rad/s), or --gyro_unit=rad/s or deg/s",
          report);
      return Status::Ok();
    }
    if (report->gyroscope_unit == GyroscopeOutputUnit::kCount) {
      return Status::Error(
          "the gyroscope's outputs are counts (--gyro_unit=count), and its calibration needs "
          "their gain to start from: give --initial_gyro_gain=G in (rad/s) per count, G = 1/S "
          "for a datasheet sensitivity S in counts per rad/s, or 0.0174533/S (pi/180/S) for S "
          "in counts per deg/s (LSB/(deg/s)); imu_tk's Xsens example starts from 1/6258: "
          "--initial_gyro_gain=0.000159795. A log already in rad/s or deg/s: --gyro_unit=rad/s "
          "or deg/s");
    }
    report->initial_gyro_gain_from = report->gyroscope_unit == GyroscopeOutputUnit::kRadPerS
                                         ? "1 for rad/s: --initial_gyro_gain not given"
                                         : "pi/180 for deg/s: --initial_gyro_gain not given";
  }
  report->gyroscope_options.initial = GyroscopeParametersWithGain(gain, gain, gain);
  return Status::Ok();
}

Status SolveMlGyroscope(const TriadLog& log, const CalibrateImuOptions& options,
                        CalibrateImuReport* report) {
  const std::string& where = GyroscopeWhere(options);
  if (report->imu_tk_status.ok()) {
    report->imu_tk_gyroscope_status =
        CalibrateImuTkGyroscope(log, report->result, report->gyroscope_options, &report->gyroscope);
    report->has_gyroscope_calibration = report->imu_tk_gyroscope_status.ok();
  } else {
    report->imu_tk_gyroscope_status =
        Status::Error("imu_tk's accelerometer calibration gave none to start from");
  }
  GyroscopeSessionOptions session;
  session.gravity_mps2 = options.session.gravity_mps2;
  session.unit = report->gyroscope_unit;
  session.initial = report->has_gyroscope_calibration ? report->gyroscope.parameters
                                                      : report->gyroscope_options.initial;
  session.alpha = options.session.alpha;
  session.turn_sampling = options.gyro_turn_sampling;
  session.latitude_given = options.latitude_given;
  session.latitude_rad = options.latitude_deg * M_PI / 180.0;
  GyroscopeSessionCalibration calibration;
  const Status status = CalibrateGyroscopeSession(log, report->pose_intervals, report->ml_options,
                                                  report->ml, session, &calibration)
                            .WithContext(where + ": the gyroscope");
  report->gyroscope_ml_options = calibration.ml_options;
  report->gyroscope_discovery_options = calibration.discovery_options;
  report->gyroscope_discovery = std::move(calibration.discovery);
  if (!status.ok()) {
    if (options.gyroscope_asked) return status;
    NoteGyroscopeNotCalibrated(log,
                               WithoutPrefix(status.message(), where + ": ") +
                                   " (give --gyro_unit or --initial_gyro_gain to make this a "
                                   "refusal)",
                               report);
    return Status::Ok();
  }
  // The calibration is the model discovery settled on (issue 44, item 7): its final fit when it
  // found effects; the baseline stays in gyroscope_discovery.
  report->gyroscope_ml = report->gyroscope_discovery.effects.empty()
                             ? std::move(calibration.ml)
                             : report->gyroscope_discovery.final_fit;
  ACCELCAL_RETURN_IF_ERROR(CheckGyroscopeMatchesUnit(report->gyroscope_ml.parameters,
                                                     report->gyroscope_ml.offset,
                                                     report->gyroscope_unit)
                               .WithContext(where));
  report->has_gyroscope_ml = true;
  return Status::Ok();
}

// Mode ml, and mode imu_tk, up to the gyroscope: the unit, the start, the gyroscope's start.
Status Start(const TriadLog& log, const CalibrateImuOptions& options, const char* mode,
             CalibrateImuReport* report, bool* gyroscope) {
  report->unit = options.session.unit;
  report->mode = mode;
  ACCELCAL_RETURN_IF_ERROR(InitialGuess(log, options, report));
  *gyroscope = log.has_gyroscope();
  if (*gyroscope) ACCELCAL_RETURN_IF_ERROR(GyroscopeStart(log, options, report, gyroscope));
  return Status::Ok();
}

}  // namespace

Status CalibrateImuModeMl(const TriadLog& log, const CalibrateImuOptions& options,
                          CalibrateImuReport* report) {
  if (options.detector != "noise_floor" && options.detector != "imu_tk") {
    return Status::Error("--detector='" + options.detector +
                         "' is not a detector; use --detector=noise_floor or imu_tk");
  }
  bool gyroscope = false;
  ACCELCAL_RETURN_IF_ERROR(Start(log, options, "ml", report, &gyroscope));
  ACCELCAL_RETURN_IF_ERROR(SolveMl(log, options, report));
  return gyroscope ? SolveMlGyroscope(log, options, report) : Status::Ok();
}

// The gyroscope's start is refused before the accelerometer's sweep, which takes seconds.
Status CalibrateImuModeImuTk(const TriadLog& log, const CalibrateImuOptions& options,
                             CalibrateImuReport* report) {
  bool gyroscope = false;
  ACCELCAL_RETURN_IF_ERROR(Start(log, options, "imu_tk", report, &gyroscope));
  ACCELCAL_RETURN_IF_ERROR(SolveImuTk(log, options, report));
  if (!gyroscope) return Status::Ok();
  const std::string& where = GyroscopeWhere(options);
  ACCELCAL_RETURN_IF_ERROR(
      CalibrateImuTkGyroscope(log, report->result, report->gyroscope_options, &report->gyroscope)
          .WithContext(where));
  ACCELCAL_RETURN_IF_ERROR(CheckGyroscopeMatchesUnit(report->gyroscope.parameters,
                                                     report->gyroscope.offset,
                                                     report->gyroscope_unit)
                               .WithContext(where));
  report->has_gyroscope_calibration = true;
  return Status::Ok();
}

}  // namespace accelcal
