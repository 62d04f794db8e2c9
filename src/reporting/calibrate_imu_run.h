#ifndef ACCELCAL_REPORTING_CALIBRATE_IMU_RUN_H_
#define ACCELCAL_REPORTING_CALIBRATE_IMU_RUN_H_

// calibrate_imu's two modes on one log already read, as functions of their options rather than
// of flags: the binary (problems/calibrate_imu.cc) and the Python module (python/) run the same
// sequence, so that the same log gives the same parameters and verdict through either.
//
// Mode ml (CalibrateImuModeMl):
//   1. the start's offsets (TriadStartOffset: the log's outputs checked against the unit);
//   2. imu_tk's calibration (its sweep of thresholds), for its intervals, which stand in when
//      the noise floor's detector refuses (or are the poses, detector "imu_tk");
//   3. one session's maximum-likelihood calibration and discovery
//      (estimation/triad/triad_session_calibration.h) into the report (TakeSessionCalibration);
//   4. with a gyroscope, imu_tk's gyroscope calibration to start from when its rules gave one,
//      then the maximum-likelihood one and its discovery (DiscoverGyroscope) on the same poses.
// Mode imu_tk (CalibrateImuModeImuTk): steps 1 and 2, then imu_tk's gyroscope calibration.
//
// tests/python/test_accelcal.py compares the module with the binary on imu_tk's Xsens log.

#include <string>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/triad/triad_session_calibration.h"
#include "models/gyroscope_units.h"
#include "reporting/calibrate_imu_report.h"

namespace accelcal {

// The defaults are calibrate_imu's flags' defaults.
struct CalibrateImuOptions {
  // g, the unit, the offsets' start, the noise floor's detector (window 0: from the rate), the
  // noise model and discovery's alpha.
  TriadSessionOptions session;
  // imu_tk's rules (--init_rest_s, --window, --interval_samples, --min_intervals).
  double init_rest_s = 50.0;
  int imu_tk_window_samples = 101;
  int interval_samples = 100;
  int min_intervals = 12;
  std::string detector = "noise_floor";  // mode ml: or "imu_tk"
  // The gyroscope, when the log has one: its unit, the gain to start from (0: the unit's
  // nominal gain, which counts do not have), and whether it was asked for (its file, unit or
  // gain given): then a gyroscope that cannot be calibrated is the run's refusal, else a note.
  GyroscopeOutputUnit gyroscope_unit = GyroscopeOutputUnit::kCount;
  double initial_gyro_gain = 0.0;
  bool gyroscope_asked = false;
  // Mode ml: discovery may put the turns' sampling error in the gyroscope's noise model
  // (docs/gyroscope.md); false: never (the turns then carry white noise and wander alone).
  bool gyro_turn_sampling = true;
  // Mode ml: the latitude of the recording (degrees north), when given: the Earth's rate's
  // vertical part is then held in the gyroscope's model.
  bool latitude_given = false;
  double latitude_deg = 0.0;
  // The names messages start with: the log's file, and the gyroscope's (its own file, or "").
  std::string log_name;
  std::string gyroscope_log_name;
};

// Fill `report`'s fields of the mode (unit, initial_offset_from, options, result, the session's,
// the gyroscope's); the caller fills what it read (log_path, log_notes, log_sha256...). They fail
// in one line, starting with the file's name where calibrate_imu's message does.
Status CalibrateImuModeMl(const TriadLog& log, const CalibrateImuOptions& options,
                          CalibrateImuReport* report);
Status CalibrateImuModeImuTk(const TriadLog& log, const CalibrateImuOptions& options,
                             CalibrateImuReport* report);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_CALIBRATE_IMU_RUN_H_
