#ifndef ACCELCAL_STUDIES_GYROSCOPE_REPEATABILITY_H_
#define ACCELCAL_STUDIES_GYROSCOPE_REPEATABILITY_H_

// Does the gyroscope's new-session sigma (estimation/gyroscope/gyroscope_sessions.h) cover a new
// session as claimed (issue 44, item 8)? Monte Carlo of devices whose gyroscope moves between
// sessions by a known sigma tau_i per unknown (the 9 parameters and the 3 offsets), each session
// a whole log simulated with both sensors (simulation/triad_log_simulator.h) and calibrated as
// `calibrate_imu --log=S1,S2,...` calibrates a session: the accelerometer's session calibration
// on the poses the noise floor finds (estimation/triad/triad_session_calibration.h), then the
// gyroscope's (CalibrateSessionGyroscope). Per device, `training_sessions` sessions are combined
// (each unknown's own tau^2, t on S - 1 dof: the device scheme, what calibrate_imu reports) and
// one more session predicted: covered when inside common +- interval_multiplier_95 x
// stddev_new_session.
//
// tau_i is `between_over_within` times unknown i's within-session sigma, read from a pilot
// session at the design's truth: where tau dominates, the pivot is Student t and the coverage
// should be 95% (slightly above when tau^2 is estimated as 0 by chance and the known within
// variance stands in). The devices are independent, so the coverage's binomial standard error
// on the devices is exact for one unknown; over the 12 unknowns of a device the predictions are
// nearly independent (each unknown's shift is drawn apart).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "estimation/gyroscope/gyroscope_ml_calibration.h"
#include "studies/gyroscope_monte_carlo.h"
#include "studies/triad_repeatability.h"

namespace accelcal {

// The gyroscope's 12 unknowns of an array's sessions (sessions[d][s]) for the leave-one-out check
// (LeaveOneSessionOutOf with GyroscopeParameterKinds()).
ArraySessionEstimates GyroscopeArrayEstimates(
    const std::vector<std::vector<GyroscopeMlResult>>& sessions);

// A hand-held session of a mimu4444-like IMU: 24 poses of 4 s at 100 Hz, the accelerometer of
// Mimu4444LikeTriad (noise 7.5, 6.8, 10.2 counts), a gyroscope like imu1's of run 1 (gains
// ~1/940 (rad/s)/count, angles up to 8e-3 rad, offsets -23, -4.5, -3.3 counts, noise 2.6, 3.0,
// 1.8 counts), g = 9.8187 m/s^2.
GyroscopeSessionDesign Mimu4444LikeGyroscopeDesign();

struct GyroscopeRepeatabilityOptions {
  int devices = 60;
  int training_sessions = 3;  // S; session S + 1 is predicted
  GyroscopeSessionDesign design = Mimu4444LikeGyroscopeDesign();
  double between_over_within = 5.0;
  uint64_t seed = 1;
  int threads = 0;  // 0: every core
};

struct GyroscopeRepeatabilityResult {
  GyroscopeRepeatabilityOptions options;
  std::array<double, kGyroscopeCalibrationCount> within_stddev{};   // the pilot's
  std::array<double, kGyroscopeCalibrationCount> between_stddev{};  // tau, simulated
  int failed_devices = 0;  // a session of the device refused (the device is skipped)
  std::string first_failure;
  std::array<CoverageCount, kTriadParameterKindCount> coverage{};  // by kind
  std::array<CoverageCount, kGyroscopeCalibrationCount> coverage_by_unknown{};
  CoverageCount coverage_all;
  // The device scheme's 95% interval of tau covering the simulated tau, every unknown.
  CoverageCount tau_interval_coverage;
  // The binomial standard error of a 95% coverage over every prediction (as if independent).
  double coverage_standard_error = 0.0;
};

// Fails on options no study can run, or when the pilot session is refused.
Status RunGyroscopeRepeatabilityMonteCarlo(const GyroscopeRepeatabilityOptions& options,
                                           GyroscopeRepeatabilityResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_GYROSCOPE_REPEATABILITY_H_
