// calibrate_imu: a three-axis accelerometer (triad) calibrated from a multi-position log, with
// no tilt table: the sensor is held still by hand in a dozen or more orientations.
//
// Mode imu_tk reproduces imu_tk's accelerometer calibration (Tedaldi, Pretto, Menegatti,
// ICRA 2014) rule for rule: static intervals where the windowed variance norm is below k times
// that of an initial rest, for k = 2..10; for each k the 9 parameters of
//   a = T K (u - b)     (docs/triad.md: 3 non-orthogonality angles, 3 gains, 3 biases)
// that minimise 1/2 sum_i (g - |a_i|)^2 over the first 100 samples of every interval of at
// least 100; the k with the lowest final cost is kept (estimation/triad/imu_tk_calibration.h).
// With a gyroscope (its columns, or --gyro_log), then imu_tk's gyroscope calibration:
//   w = T K (u - b)     (docs/gyroscope.md: 6 angles, 3 gains in (rad/s) per unit, 3 offsets)
// with b the initial rest's mean and the 9 others minimising 1/2 sum |R^T g_before - g_after|^2
// over the turns between consecutive intervals (estimation/gyroscope/); --imu_tk_calib_out
// writes imu_tk's two .calib files.
// Mode ml: the maximum-likelihood problem (estimation/triad/triad_ml_calibration.h) on the poses of
// --detector (the log's noise floor, or imu_tk's intervals at its chosen k): each pose's mean u_p
// against b + K^-1 T^-1 g n_p with an unknown unit direction n_p per pose, whitened by the noise
// model of the pose means (--noise: white, s_k^2 / N_p, or the poses' Allan variance),
//   min 1/2 sum_p |(ubar_p - u_p) / sigma_p|^2,
// started from the poses' own spread; every parameter +- sigma (ceres::Covariance), the
// chi-square fit statistic on P - 9 degrees of freedom, discovery, and the differences from
// imu_tk in sigma. The sequence is estimation/triad/triad_session_calibration.h's, which the
// sessions path (--log=S1,S2,..., calibrate_imu_sessions.cc) runs on every session.
//
// Inputs: the log in any layout io/imu_log.h reads (docs/log-layouts.md: imu_tk's ASCII t x y z,
// CSV and other text with a header, .mat, a ROS 2 bag's Imu messages), in the sensor's own unit;
// its gyroscope's columns or imu_tk's pair of files (--gyro_log), which mode imu_tk calibrates too.
// Outputs: the sweep, the chosen k, the parameters and the static intervals on stdout; JSON
// with --json.
//
//   build/bin/calibrate_imu --log=../shared/data/imu_tk-xsens/xsens_acc.mat --g=9.81744 \
//       --mode=imu_tk --init_rest_s=50 --initial_offset=32768 --json=imu_tk.json
//   (and the same with --mode=ml --json=ml.json)

#include <gflags/gflags.h>

#include <array>
#include <cmath>
#include <iostream>
#include <map>

#include "estimation/gyroscope/gyroscope_discovery.h"
#include "estimation/gyroscope/gyroscope_ml_calibration.h"
#include "estimation/gyroscope/imu_tk_gyroscope_calibration.h"
#include "estimation/triad/imu_tk_calibration.h"
#include "estimation/triad/triad_pose_noise.h"
#include "estimation/triad/triad_session_calibration.h"
#include "io/calibration_file.h"
#include "io/csv_reader.h"
#include "io/imu_log.h"
#include "io/imu_tk_calib_file.h"
#include "io/imucal_calibration_json.h"
#include "io/imucal_session.h"
#include "io/json_file.h"
#include "io/output_paths.h"
#include "io/provenance.h"
#include "models/gyroscope_units.h"
#include "models/triad_units.h"
#include "problem_support.h"
#include "reporting/calibrate_imu_report.h"
#include "reporting/calibrate_imu_run.h"
#include "reporting/ferraris_report.h"
#include "reporting/triad_report.h"

// clang-format off
DEFINE_string(log, "", "The IMU log, in the layout its tool wrote (docs/log-layouts.md): CSV, ';'-, tab- or blank-separated text with a header naming the columns (t/time/timestamp, ax/acc_x/ACCEL_X..., gyroscope gx/gyr_x/... kept), metadata lines before it or not; imu_tk's ASCII layout (4 blank-separated columns: t [s], x, y, z, whatever the file's suffix); or a MATLAB .mat (v5 or v7.3) with the variables named; or a ROS 2 bag (its folder with metadata.yaml, or its .db3 file) whose sensor_msgs/msg/Imu messages are read (--topic, --bag_time), in m/s^2 and rad/s. Values in the sensor's unit (e.g. raw counts). Several sessions: --log=S1,S2,...");
ACCELCAL_DEFINE_IMU_LOG_FLAGS();
ACCELCAL_DEFINE_GYRO_LOG_FLAG();
DEFINE_string(mode, "imu_tk", "imu_tk: imu_tk's calibration reproduced (its cost, static detector and threshold sweep). ml: maximum likelihood on the poses of --detector (each pose's mean, unknown gravity direction per pose, white noise), with the covariance of every parameter and a chi-square fit statistic, beside imu_tk's result when its rules give one. ferraris: imucal's closed form on the six holds of --session, and the least squares they allow.");
DEFINE_double(g, 9.81, "Local gravity in m/s^2 (imu_tk's default 9.81; its Xsens example uses 9.81744). Earth's surface gravity is 9.76 to 9.84 m/s^2, so 9.7 to 9.9 is accepted: the flag is in m/s^2, not in g, and a wrong g scales every gain by g_stated / g_true, which static poses cannot detect.");
DEFINE_string(unit, "count", "The unit of the log's outputs: count (raw ADC counts, as imu_tk's example), m/s^2 or g. It sets the units of the gains ((m/s^2) per unit) and offsets (the unit); a calibration whose gains contradict it (e.g. gains near 1 from a log said to be in counts) is refused.");
DEFINE_double(init_rest_s, 50.0, "Duration in s of the initial rest the imu_tk thresholds are scaled from (imu_tk's library default is 30; its Xsens example, and this default, 50). A rest that holds motion is refused, with the time the sensor starts moving.");
DEFINE_string(initial_offset, "auto", "Initial guess of the three offsets b, in the log's unit: auto (the output of an ideal sensor at zero specific force: 0 for m/s^2 and g; for counts the ADC's mid-scale, 2^(n-1) for outputs all in [0, 2^n), else 0) or a number (imu_tk's default 0; 32768 for a 16-bit ADC centred at mid-scale, as in its Xsens example). The gains start at 1 per unit (9.80665 for --unit=g) and the angles at 0, as in imu_tk.");
DEFINE_int32(window, 101, "Static detector: window of the variance, in samples (odd, imu_tk's 101). Detector noise_floor, when not given: about 1 s of samples, imu_tk's 101 at 60 Hz and up, the rate's samples per second made odd below (25 at 25 Hz, at least 11).");
DEFINE_int32(interval_samples, 100, "Samples used from each static interval, and the minimum length of an interval used (imu_tk's 100).");
DEFINE_int32(min_intervals, 12, "Fewest static intervals a threshold must give to be solved (imu_tk's 12).");
DEFINE_string(detector, "noise_floor", "Mode ml: the static detector. noise_floor: thresholds from the log's own noise floor, no initial rest needed (estimation/triad/noise_floor_detector.h); when it finds too few poses, imu_tk's intervals are used if its rules give them (said so in the output). imu_tk: imu_tk's intervals at its chosen k. Mode imu_tk always uses imu_tk's.");
DEFINE_double(threshold_factor, 10.0, "Detector noise_floor: a window is still when its variance is below this times the noise floor's on every axis (white noise crosses 10 with probability 2e-148 at 101 samples; motion reaches 100 to 100000).");
DEFINE_double(min_interval_s, 1.0, "Detector noise_floor: static intervals shorter than this (s) are listed apart and not used.");
DEFINE_string(session, "", "Mode ferraris: imucal's annotated session CSV (header part,samples,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z; raw counts; the six holds and three turns labelled in part), docs/imucal.md.");
DEFINE_string(reference, "", "Mode ferraris: an imucal calibration JSON (e.g. its example_cal.json) to show beside the closed form, with the largest relative difference.");
DEFINE_double(sampling_rate_hz, 0.0, "Mode ferraris: the session's sampling rate in Hz, needed for the gyroscope's turns (imucal's example: 204.8); 0 calibrates the accelerometer only.");
DEFINE_bool(scale_nonlinearity, false, "Mode ml: estimate a second-order scale term per axis too (scale_nonlinearity_x/y/z, 1/(m/s^2), the spec's k2: the axis reads w + k2 w^2 for a force w along it), 12 parameters in all, written to the calibration file (format_version 2, the 9-parameter fit beside them) and applied by apply.");
DEFINE_string(noise, "auto", "Mode ml: the noise model of the pose means. white: white noise of the pooled within-pose variance, s^2/N for a pose of N samples. allan: the Allan variance of the poses' own samples (N, B, K fitted per axis), a pose of T s has variance sigma^2(T) (docs/noise.md). auto: allan when white noise is rejected against it from the within-pose data at alpha/4, else white. The parameters' sigmas and the fit statistic follow it.");
DEFINE_double(alpha, 0.01, "Mode ml: discovery's family-wise error rate, in (0, 0.5): a session the 9-parameter model and its noise model explain gets any verdict but explained at most this often (docs/triad-discovery.md).");
DEFINE_string(json, "", "Write the results as JSON to this file (written atomically).");
DEFINE_string(report, "", "Mode ml: write a self-contained HTML report to this file (the poses, each pose's whitened residual, the parameters +- sigma beside imu_tk's and the datasheet's, the fit; figures embedded, drawn by tools/plot_triad.py with /usr/bin/python3 when it has matplotlib). Written atomically with the other outputs.");
DEFINE_string(gyro_unit, "count", "Modes imu_tk and ml, a log with a gyroscope (its columns, or --gyro_log): the unit of the gyroscope's outputs, count (raw ADC counts, as imu_tk's example), rad/s or deg/s; by default the unit the gyroscope columns' names state (gyr_x_dps), else count. It sets the units of the gyroscope's gains ((rad/s) per unit) and offsets (the unit).");
DEFINE_double(initial_gyro_gain, 0.0, "Modes imu_tk and ml, a log with a gyroscope: the gyroscope's gain to start from, in rad/s per unit of its output, the same for the three axes (the angles start at 0). Not given: 1 for --gyro_unit=rad/s, pi/180 for deg/s; counts need it: 1/S for a datasheet sensitivity S in counts per rad/s, (pi/180)/S for S in counts per deg/s (LSB/(deg/s)). imu_tk's Xsens example: 1/6258 = 0.000159795.");
DEFINE_string(gyro_bias, "rest", "Mode imu_tk: how the gyroscope's offset is found. rest (the only value): imu_tk's rule, the mean of its output over the initial rest (--init_rest_s), subtracted and not estimated.");
DEFINE_string(imu_tk_calib_out, "", "Mode imu_tk: write imu_tk's calibration files PREFIX_acc.calib and PREFIX_gyro.calib (the gyroscope's only when the log has one), byte for byte the text imu_tk's CalibratedTriad_::save writes and its load reads: the misalignment matrix, the scale matrix (gains on its diagonal) and the bias vector (offsets, the log's unit), 6 significant digits (docs/gyroscope.md). Written atomically with the other outputs, nothing on failure.");
DEFINE_string(calibration_out, "", "Mode ml: write the calibration file (docs/calibration.md, geometry triad: parameters, units, covariance, output unit, g, fit, input checksums) that apply reads. Written atomically, nothing on failure.");
DEFINE_double(latitude_deg, 1000.0, "Mode ml, a log with a gyroscope: the latitude where it was recorded, in degrees north (-90 to 90; south negative). The Earth's rate (7.292e-5 rad/s) then has a known vertical part, Omega sin(latitude) rad/s about the up direction in every pose, which the model holds; without it that part is estimated with the prior N(0, Omega^2) and reported, never taken for a g-sensitivity (docs/gyroscope.md). Not given: unknown.");
DEFINE_bool(gyro_turn_sampling, true, "Mode ml, a log with a gyroscope: discovery may add the turns' sampling error to the gyroscope's noise model when the turns reject it without (each turn's angle variance kappa^2 times the sum of its rate's squared changes between samples times the steps squared, rad^2: what samples cannot resolve of a turn that starts or stops abruptly; docs/gyroscope.md). false: never, as before; the turns' shape checks then say what remains.");
// clang-format on

ACCELCAL_FLAG_RANGE(g, 9.7, 9.9);
ACCELCAL_FLAG_OPEN_RANGE(init_rest_s, 0.0, 1e6);
ACCELCAL_RENAMED_FLAG(initial_bias, initial_offset);
ACCELCAL_FLAG_RANGE(window, 11, 100001);
ACCELCAL_FLAG_RANGE(interval_samples, 2, 1000000);
ACCELCAL_FLAG_RANGE(min_intervals, 3, 100000);
ACCELCAL_FLAG_RANGE(threshold_factor, 1.0, 1e6);
ACCELCAL_FLAG_RANGE(min_interval_s, 0.0, 1e6);
ACCELCAL_FLAG_RANGE(sampling_rate_hz, 0.0, 1e6);
ACCELCAL_FLAG_RANGE(initial_gyro_gain, 0.0, 100.0);

namespace accelcal {
namespace {

constexpr char kUsage[] =
    "Calibrates a three-axis accelerometer from a multi-position log (no tilt table).\n"
    "Model a = T K (u - b) (docs/triad.md): angles in rad, gains K in (m/s^2) per unit of the\n"
    "output (--unit=count|m/s^2|g), offsets b in that unit.\n"
    "Mode imu_tk reproduces imu_tk: cost 1/2 sum (g - |a|)^2 in (m/s^2)^2, thresholds k = 2..10\n"
    "times an initial rest's variance norm; with a gyroscope (its columns, or --gyro_log) its\n"
    "gyroscope calibration too: w = T K (u - b) in rad/s, 6 angles in rad, gains K in (rad/s) per\n"
    "unit (--gyro_unit=count|rad/s|deg/s, --initial_gyro_gain), offsets b the initial rest's mean\n"
    "(docs/gyroscope.md); --imu_tk_calib_out=PREFIX writes imu_tk's .calib files.\n"
    "Mode ml: maximum likelihood on static poses found from the log's own noise floor (pose\n"
    "means, unknown gravity directions, white noise): every parameter +- sigma, a chi-square fit\n"
    "statistic, imu_tk's answer beside it, and --calibration_out for apply; with a gyroscope\n"
    "(in rad/s or deg/s by its columns' names, or --gyro_unit with --initial_gyro_gain), its\n"
    "calibration jointly with the accelerometer's poses: w = T K (u - b) +- sigma, offsets from\n"
    "every pose, the fit, the Earth's rate against the noise, discovery (docs/gyroscope.md).\n"
    "Mode ferraris: imucal's closed form on its six holds (--session), and the least squares\n"
    "that six holds allow (docs/imucal.md).\n"
    "Exit status: 0 on success, 2 on bad input (one line on stderr; nothing is written).\n\n"
    "  calibrate_imu --log=xsens_acc.mat --g=9.81744 --mode=imu_tk|ml [--json=out.json]\n"
    "  calibrate_imu --log=xsens_acc.mat --gyro_log=xsens_gyro.mat --g=9.81744 --mode=imu_tk\n"
    "      --initial_gyro_gain=0.000159795 [--imu_tk_calib_out=test_imu]\n"
    "  calibrate_imu --log=xsens_acc.mat --gyro_log=xsens_gyro.mat --g=9.81744 --mode=ml\n"
    "      --initial_gyro_gain=0.000159795 [--calibration_out=cal.json]\n"
    "  calibrate_imu --mode=ferraris --session=annotated_session.csv [--reference=cal.json]";

// --imu_tk_calib_out's file of `sensor` ("acc" or "gyro"), as imu_tk's example names them
// (test_imu_acc.calib), or "" when not asked for.
std::string ImuTkCalibPath(const char* sensor) {
  return FLAGS_imu_tk_calib_out.empty() ? "" : FLAGS_imu_tk_calib_out + "_" + sensor + ".calib";
}

bool FlagGiven(const char* name) { return !gflags::GetCommandLineFlagInfoOrDie(name).is_default; }

}  // namespace

// The flags of imu_tk's gyroscope calibration, their values alone (what the log holds is checked
// once it is read, GyroscopeStart). Also the sessions path's (calibrate_imu_sessions.cc).
Status ValidateGyroscopeFlags() {
  GyroscopeOutputUnit unit;
  ACCELCAL_RETURN_IF_ERROR(
      ParseGyroscopeOutputUnit(FLAGS_gyro_unit, &unit).WithContext("--gyro_unit"));
  if (FLAGS_gyro_bias != "rest") {
    return Status::Error("--gyro_bias='" + FLAGS_gyro_bias +
                         "' is not supported; the one rule is rest (imu_tk's: the mean of the "
                         "gyroscope's output over the initial rest, --init_rest_s, not estimated)");
  }
  if (FlagGiven("initial_gyro_gain") && !(FLAGS_initial_gyro_gain > 0.0)) {
    return Status::Error(StringPrintf(
        "--initial_gyro_gain=%g is not a gain; give the start's gain in rad/s per unit of the "
        "gyroscope's output, > 0 (imu_tk's Xsens example: 1/6258 = 0.000159795 per count)",
        FLAGS_initial_gyro_gain));
  }
  if (!FLAGS_imu_tk_calib_out.empty() && FLAGS_imu_tk_calib_out.back() == '/') {
    return Status::Error(
        "--imu_tk_calib_out='" + FLAGS_imu_tk_calib_out +
        "' names a folder; give a prefix, e.g. --imu_tk_calib_out=" + FLAGS_imu_tk_calib_out +
        "test_imu (writes test_imu_acc.calib and test_imu_gyro.calib there)");
  }
  return Status::Ok();
}

// The gyroscope's flags belong to mode imu_tk; elsewhere (`where`: "--mode=ml", "several
// sessions") one given is refused rather than ignored.
Status RefuseGyroscopeFlags(const std::string& where) {
  for (const char* name : {"gyro_unit", "initial_gyro_gain", "gyro_bias", "imu_tk_calib_out"}) {
    if (FlagGiven(name)) {
      return Status::Error(
          std::string("--") + name + " belongs to " +
          (std::string(name) == "imu_tk_calib_out"
               ? "--mode=imu_tk, which calibrates by imu_tk's rules and writes its files"
               : "--mode=imu_tk and --mode=ml, which calibrate the gyroscope of a log") +
          "; " + where + " does not read it");
    }
  }
  return Status::Ok();
}

namespace {

Status ValidateFlags() {
  if (FLAGS_mode != "imu_tk" && FLAGS_mode != "ml" && FLAGS_mode != "ferraris") {
    return Status::Error("--mode='" + FLAGS_mode +
                         "' is not a mode; use --mode=imu_tk, ml or ferraris");
  }
  ACCELCAL_RETURN_IF_ERROR(ValidateGyroscopeFlags());
  if (FLAGS_mode == "ferraris")
    ACCELCAL_RETURN_IF_ERROR(RefuseGyroscopeFlags("--mode=" + FLAGS_mode));
  if (FlagGiven("latitude_deg") && !(std::abs(FLAGS_latitude_deg) <= 90.0)) {
    return Status::Error(StringPrintf(
        "--latitude_deg=%g is not a latitude; give degrees north in [-90, 90] (south negative), "
        "e.g. --latitude_deg=59.35 for Stockholm",
        FLAGS_latitude_deg));
  }
  if (FLAGS_mode != "ml" && FlagGiven("latitude_deg")) {
    return Status::Error(
        "--latitude_deg belongs to --mode=ml, whose gyroscope model holds the "
        "Earth's rate; --mode=" +
        FLAGS_mode + " does not read it");
  }
  if (FLAGS_mode != "ml" && FlagGiven("gyro_turn_sampling")) {
    return Status::Error(
        "--gyro_turn_sampling belongs to --mode=ml, whose discovery chooses the "
        "gyroscope's noise model; --mode=" +
        FLAGS_mode + " does not read it");
  }
  if (FLAGS_mode == "ml" && !FLAGS_imu_tk_calib_out.empty()) {
    return Status::Error(
        "--imu_tk_calib_out belongs to --mode=imu_tk, whose result imu_tk's files hold; "
        "--mode=ml writes its calibration with --calibration_out");
  }
  if (FLAGS_mode == "ml" && FlagGiven("gyro_bias")) {
    return Status::Error(
        "--gyro_bias belongs to --mode=imu_tk; --mode=ml estimates the gyroscope's offsets from "
        "every pose's mean");
  }
  TriadNoiseChoice noise;
  ACCELCAL_RETURN_IF_ERROR(ParseTriadNoiseChoice(FLAGS_noise, &noise).WithContext("--noise"));
  if (!(FLAGS_alpha > 0.0 && FLAGS_alpha < 0.5)) {
    return Status::Error(
        StringPrintf("--alpha=%g is not in (0, 0.5); give e.g. --alpha=0.01", FLAGS_alpha));
  }
  if (FLAGS_mode == "ferraris") {
    if (FLAGS_session.empty() || !FLAGS_log.empty()) {
      return Status::Error(
          "--mode=ferraris reads --session (imucal's annotated session CSV), not --log");
    }
    if (!FLAGS_report.empty())
      return Status::Error("--report needs --mode=ml: the report shows the ml fit's poses");
    if (!FLAGS_calibration_out.empty()) {
      return Status::Error(
          "--calibration_out needs --mode=ml: six holds cannot determine the triad's angles "
          "(docs/imucal.md), so no full calibration with covariance comes from them");
    }
    return CheckOutputPaths({{"--json", FLAGS_json}},
                            RunInputs{{FLAGS_session, FLAGS_reference}, {}});
  }
  if (FLAGS_log.empty())
    return Status::Error("--log is required: the accelerometer log to calibrate");
  TriadOutputUnit unit;
  ACCELCAL_RETURN_IF_ERROR(ParseTriadOutputUnit(FLAGS_unit, &unit).WithContext("--unit"));
  double offset = 0.0;
  if (FLAGS_initial_offset != "auto" &&
      (!ParseFiniteNumber(FLAGS_initial_offset, &offset) || std::fabs(offset) > 1e9)) {
    return Status::Error("--initial_offset='" + FLAGS_initial_offset +
                         "' is neither auto nor a finite number within +-1e9 (the log's unit)");
  }
  if (!FLAGS_session.empty() || !FLAGS_reference.empty())
    return Status::Error("--session and --reference belong to --mode=ferraris");
  if (FLAGS_window % 2 == 0) {
    return Status::Error("--window=" + std::to_string(FLAGS_window) +
                         " is even; the window is centred on its sample, give an odd number");
  }
  if (FLAGS_detector != "noise_floor" && FLAGS_detector != "imu_tk") {
    return Status::Error("--detector='" + FLAGS_detector +
                         "' is not a detector; use --detector=noise_floor or imu_tk");
  }
  if (FLAGS_scale_nonlinearity && FLAGS_mode != "ml")
    return Status::Error("--scale_nonlinearity needs --mode=ml");
  if (!FLAGS_calibration_out.empty() && FLAGS_mode != "ml") {
    return Status::Error(
        "--calibration_out needs --mode=ml: a calibration file carries the parameters' "
        "covariance, and imu_tk's cost gives none");
  }
  if (!FLAGS_report.empty() && FLAGS_mode != "ml") {
    return Status::Error(
        "--report needs --mode=ml: the report shows each pose's residual, which imu_tk's cost "
        "does not give");
  }
  return CheckOutputPaths({{"--json", FLAGS_json},
                           {"--calibration_out", FLAGS_calibration_out},
                           {"--report", FLAGS_report},
                           {"--imu_tk_calib_out", ImuTkCalibPath("acc")},
                           {"--imu_tk_calib_out", ImuTkCalibPath("gyro")}},
                          RunInputs{{FLAGS_log, FLAGS_gyro_log}, {}});
}

Status Load(TriadLog* log, CalibrateImuReport* report, DataSource* source) {
  ImuLogReadOptions read_options;
  ACCELCAL_RETURN_IF_ERROR(ImuLogOptionsFromFlags(FLAGS_columns, FLAGS_rate_hz, FLAGS_time_unit,
                                                  FLAGS_gyro_log, FLAGS_topic, FLAGS_bag_time,
                                                  &read_options));
  ImuLogSource log_source;
  ACCELCAL_RETURN_IF_ERROR(
      ReadImuLog(FLAGS_log, read_options, log, ImuLogSpacing::kEven, &log_source));
  std::map<std::string, std::string> files = {{"log", FLAGS_log}};
  if (!FLAGS_gyro_log.empty()) files["log_gyroscope"] = FLAGS_gyro_log;
  ACCELCAL_RETURN_IF_ERROR(DescribeMeasuredData("", files, source));
  report->log_path = FLAGS_log;
  report->log_layout = log_source.layout;
  report->log_notes = log_source.notes;
  report->log_timing = log_source.timing;
  report->log_metadata = log_source.metadata;
  ACCELCAL_RETURN_IF_ERROR(
      TakeStatedUnit(log_source, &FLAGS_unit, &report->log_notes).WithContext(FLAGS_log));
  if (log->has_gyroscope()) {
    report->gyroscope_samples = log->gyroscope.size();
    report->gyroscope_path = FLAGS_gyro_log;
    if (!FLAGS_gyro_log.empty())
      report->gyroscope_sha256 = source->files.at("log_gyroscope").sha256;
    report->log_notes.push_back(
        "gyroscope: read (" + std::to_string(log->gyroscope.size()) + " samples); " +
        (FLAGS_mode == "imu_tk" ? std::string("calibrated below by imu_tk's rules")
                                : std::string("calibrated below by maximum likelihood")));
    ACCELCAL_RETURN_IF_ERROR(TakeStatedUnitOf(log_source.gyroscope_unit,
                                              {"count", "rad/s", "deg/s"}, "gyro_unit",
                                              "gyroscope outputs", "gyroscope", &FLAGS_gyro_unit,
                                              &report->log_notes, log_source.units_stated_by)
                                 .WithContext(FLAGS_gyro_log.empty() ? FLAGS_log : FLAGS_gyro_log));
  } else {
    for (const char* name : {"gyro_unit", "initial_gyro_gain", "gyro_bias"}) {
      if (FlagGiven(name)) {
        return Status::Error(FLAGS_log + ": --" + name +
                             " is for the gyroscope, and the log has none: give imu_tk's "
                             "gyroscope file with --gyro_log=FILE, or a log with gyroscope columns "
                             "(gx, gy, gz; docs/log-layouts.md)");
      }
    }
  }
  report->log_sha256 = source->files.at("log").sha256;
  report->sample_count = log->size();
  report->first_t_s = log->timestamp_s.front();
  report->last_t_s = log->timestamp_s.back();
  return Status::Ok();
}

}  // namespace

// Mode ml's options, one session's and every session's of --log=S1,S2,...
// (problems/calibrate_imu_sessions.cc), from the flags both paths share.
Status TriadSessionOptionsFromFlags(TriadSessionOptions* options) {
  ACCELCAL_RETURN_IF_ERROR(ParseTriadOutputUnit(FLAGS_unit, &options->unit).WithContext("--unit"));
  options->gravity_mps2 = FLAGS_g;
  options->offset.automatic = FLAGS_initial_offset == "auto";
  if (!options->offset.automatic &&
      !ParseFiniteNumber(FLAGS_initial_offset, &options->offset.value)) {
    return Status::Error("--initial_offset='" + FLAGS_initial_offset +
                         "' is neither auto nor a finite number (the log's unit)");
  }
  // 0: the noise floor's window from the log's rate (DefaultNoiseFloorWindow); imu_tk's
  // detector keeps its 101 samples.
  options->detector.window_samples =
      gflags::GetCommandLineFlagInfoOrDie("window").is_default ? 0 : FLAGS_window;
  options->detector.threshold_factor = FLAGS_threshold_factor;
  options->detector.min_interval_s = FLAGS_min_interval_s;
  options->scale_nonlinearity = FLAGS_scale_nonlinearity;
  ACCELCAL_RETURN_IF_ERROR(
      ParseTriadNoiseChoice(FLAGS_noise, &options->noise).WithContext("--noise"));
  options->alpha = FLAGS_alpha;
  return Status::Ok();
}

namespace {

// The flags as the options of calibrate_imu's two modes (reporting/calibrate_imu_run.h), which
// run the modes' sequences; the Python module runs the same.
Status Solve(const TriadLog& log, CalibrateImuReport* report) {
  CalibrateImuOptions options;
  ACCELCAL_RETURN_IF_ERROR(TriadSessionOptionsFromFlags(&options.session));
  options.init_rest_s = FLAGS_init_rest_s;
  options.imu_tk_window_samples = FLAGS_window;
  options.interval_samples = FLAGS_interval_samples;
  options.min_intervals = FLAGS_min_intervals;
  options.detector = FLAGS_detector;
  ACCELCAL_RETURN_IF_ERROR(ParseGyroscopeOutputUnit(FLAGS_gyro_unit, &options.gyroscope_unit)
                               .WithContext("--gyro_unit"));
  options.initial_gyro_gain = FlagGiven("initial_gyro_gain") ? FLAGS_initial_gyro_gain : 0.0;
  options.gyro_turn_sampling = FLAGS_gyro_turn_sampling;
  options.latitude_given = FlagGiven("latitude_deg");
  options.latitude_deg = FLAGS_latitude_deg;
  // Asked for: a gyroscope that cannot be calibrated is then the run's refusal, else a note
  // (--gyro_bias and --imu_tk_calib_out belong to mode imu_tk; mode ml refuses them).
  options.gyroscope_asked = !FLAGS_gyro_log.empty() || FlagGiven("gyro_unit") ||
                            FlagGiven("initial_gyro_gain") || FlagGiven("gyro_bias") ||
                            !FLAGS_imu_tk_calib_out.empty();
  options.log_name = FLAGS_log;
  options.gyroscope_log_name = FLAGS_gyro_log;
  return FLAGS_mode == "ml" ? CalibrateImuModeMl(log, options, report)
                            : CalibrateImuModeImuTk(log, options, report);
}

// Mode imu_tk, --imu_tk_calib_out: imu_tk's two .calib files' text (the gyroscope's only when
// it was calibrated).
void ImuTkCalibFiles(CalibrateImuReport* report, std::string* acc_text, std::string* gyro_text) {
  report->imu_tk_calib_acc_path = ImuTkCalibPath("acc");
  *acc_text = ImuTkCalibText(ImuTkAccelerometerTriad(report->result.best().parameters));
  if (!report->has_gyroscope_calibration) return;
  report->imu_tk_calib_gyro_path = ImuTkCalibPath("gyro");
  *gyro_text =
      ImuTkCalibText(ImuTkGyroscopeTriad(report->gyroscope.parameters, report->gyroscope.offset));
}

// Mode ferraris: imucal's closed form on its six holds, and what least squares can say.
Status RunFerraris(std::string* table) {
  FerrarisReport report;
  report.session_path = FLAGS_session;
  report.options.gravity_mps2 = FLAGS_g;
  report.options.sampling_rate_hz = FLAGS_sampling_rate_hz;
  std::map<std::string, std::string> files = {{"session", FLAGS_session}};
  ACCELCAL_RETURN_IF_ERROR(ReadImucalSession(FLAGS_session, &report.session));
  if (!FLAGS_reference.empty()) {
    ACCELCAL_RETURN_IF_ERROR(ReadImucalCalibrationJson(FLAGS_reference, &report.reference));
    report.has_reference = true;
    report.reference_path = FLAGS_reference;
    files["reference"] = FLAGS_reference;
  }
  ACCELCAL_RETURN_IF_ERROR(AnalyzeFerraris(report.session, report.options,
                                           FerrarisLeastSquaresOptions(), &report.analysis)
                               .WithContext(FLAGS_session));
  DataSource source;
  ACCELCAL_RETURN_IF_ERROR(DescribeMeasuredData("", files, &source));
  std::string json_text;
  if (!FLAGS_json.empty())
    ACCELCAL_RETURN_IF_ERROR(JsonText(WithProvenance(FerrarisJson(report), source), &json_text));
  ACCELCAL_RETURN_IF_ERROR(WriteOutputFiles({{FLAGS_json, json_text}}));
  *table = WithDataLine(source, FerrarisTable(report));
  return Status::Ok();
}

}  // namespace
// --log=S1,S2,...: several sessions of one device (problems/calibrate_imu_sessions.cc).
int RunCalibrateImuSessions();
namespace {

int Run(int argc, char** argv) {
  if (!InitProblem("calibrate_imu", kUsage, "problems/calibrate_imu", &argc, &argv))
    return kExitBadInput;
  if (FLAGS_log.find(',') != std::string::npos) return RunCalibrateImuSessions();
  if (FLAGS_mode == "ferraris") {
    std::string table;
    Status status = ValidateFlags();
    if (status.ok()) status = RunFerraris(&table);
    if (!status.ok()) return ExitWithError("calibrate_imu", status);
    std::cout << table << std::flush;
    return 0;
  }
  TriadLog log;
  CalibrateImuReport report;
  DataSource source;
  std::string json_text;
  std::string calibration_text;
  std::string report_html;
  std::string acc_calib_text;
  std::string gyro_calib_text;
  FigureOutcome figures;
  Status status = ValidateFlags();
  if (status.ok()) status = Load(&log, &report, &source);
  if (status.ok()) status = Solve(log, &report);
  if (status.ok() && !FLAGS_imu_tk_calib_out.empty())
    ImuTkCalibFiles(&report, &acc_calib_text, &gyro_calib_text);
  if (status.ok() && !FLAGS_json.empty())
    status = JsonText(WithProvenance(CalibrateImuJson(report), source), &json_text);
  if (status.ok() && !FLAGS_calibration_out.empty()) {
    CalibrationRecord record = TriadCalibrationRecord(report, source);
    status = AddGyroscopeSection(report, &record);
    if (status.ok()) status = JsonText(CalibrationJson(record), &calibration_text);
  }
  if (status.ok() && !FLAGS_report.empty()) {
    status = TriadReportHtml(log, report, source,
                             {DefaultToolsDir(ACCELCAL_TOOLS_DIR), "/usr/bin/python3"},
                             &report_html, &figures);
  }
  if (status.ok()) {
    status = WriteOutputFiles({{FLAGS_json, json_text},
                               {FLAGS_calibration_out, calibration_text},
                               {FLAGS_report, report_html},
                               {report.imu_tk_calib_acc_path, acc_calib_text},
                               {report.imu_tk_calib_gyro_path, gyro_calib_text}});
  }
  if (!status.ok()) return ExitWithError("calibrate_imu", status);
  std::cout << WithDataLine(source, CalibrateImuTable(report, FLAGS_v >= 1));
  if (!FLAGS_report.empty())
    std::cout << "report: " << FLAGS_report << " (figures: " << FigureOutcomeLine(figures) << ")\n";
  std::cout << std::flush;
  return 0;
}

}  // namespace
}  // namespace accelcal

int main(int argc, char** argv) {
  return accelcal::GuardedMain("calibrate_imu", accelcal::Run, argc, argv);
}
