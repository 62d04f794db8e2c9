#ifndef ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_SESSION_CALIBRATION_H_
#define ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_SESSION_CALIBRATION_H_

// One session's gyroscope, the one sequence behind `calibrate_imu --mode=ml` with a gyroscope
// (reporting/calibrate_imu_run.h), `calibrate_imu --log=S1,S2,...` (each session of a device)
// and triad_repeatability (each session of an array), after the accelerometer's session
// calibration (estimation/triad/triad_session_calibration.h) has found the poses and fitted them:
//
//   1. the maximum-likelihood options: g, the unit, the start, the counts' quantisation step;
//   2. discovery (estimation/gyroscope/gyroscope_discovery.h), whose baseline, the 12-unknown
//      model with its noise model (a bias wander when the poses need one), is the calibration
//      reported (CalibrateGyroscopeMl, estimation/gyroscope/gyroscope_ml_calibration.h).
//
// The caller checks the result against the unit (CheckGyroscopeMatchesUnit): calibrate_imu
// words that refusal apart from discovery's.

#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/gyroscope/gyroscope_discovery.h"
#include "estimation/gyroscope/gyroscope_ml_calibration.h"
#include "estimation/triad/static_intervals.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "models/gyroscope.h"
#include "models/gyroscope_units.h"

namespace accelcal {

struct GyroscopeSessionOptions {
  double gravity_mps2 = 9.81;
  GyroscopeOutputUnit unit = GyroscopeOutputUnit::kCount;
  GyroscopeParameters initial = GyroscopeParametersWithGain(1.0, 1.0, 1.0);  // the start
  double alpha = 0.01;  // discovery's, as the triad's
  // Discovery may put the turns' sampling error in the noise model (GyroscopeDiscoveryOptions).
  bool turn_sampling = true;
  // The latitude of the recording, when given (GyroscopeMlOptions::latitude_given).
  bool latitude_given = false;
  double latitude_rad = 0.0;
};

struct GyroscopeSessionCalibration {
  GyroscopeMlOptions ml_options;  // as run
  GyroscopeDiscoveryOptions discovery_options;
  GyroscopeDiscoveryResult discovery;
  GyroscopeMlResult ml;  // discovery.baseline: the calibration reported
};

// `intervals`, `accelerometer_options`, `accelerometer`: the accelerometer's poses and fit, as
// CalibrateGyroscopeMl takes them. Fails as discovery does (no context added).
Status CalibrateGyroscopeSession(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                                 const TriadMlOptions& accelerometer_options,
                                 const TriadMlResult& accelerometer,
                                 const GyroscopeSessionOptions& options,
                                 GyroscopeSessionCalibration* calibration);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_SESSION_CALIBRATION_H_
