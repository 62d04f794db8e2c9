#ifndef ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_SESSIONS_H_
#define ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_SESSIONS_H_

// Repeatability of the gyroscope (issue 44, item 8): several sessions of one device, each
// session's gyroscope calibrated as the single-session `calibrate_imu --mode=ml` calibrates it
// (estimation/gyroscope/gyroscope_session_calibration.h, on that session's accelerometer poses),
// then each of its 12 unknowns (the 9 parameters, the 3 offsets) combined across sessions by the
// accelerometer's random-effects model (estimation/triad/triad_sessions.h: tau^2 Paule-Mandel,
// stddev_new_session, interval_multiplier_95), and each session checked against the others
// (CheckSessionDrift). docs/repeatability.md.
//
// A session whose gyroscope is not calibrated (its log has none, its outputs are counts and no
// gain to start from was given, or its calibration refused) is named with the reason and left
// out of the combination; the others are combined when they are 2 or more.

#include <array>
#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/gyroscope/gyroscope_ml_calibration.h"
#include "estimation/gyroscope/gyroscope_session_calibration.h"
#include "estimation/triad/triad_session_calibration.h"
#include "estimation/triad/triad_sessions.h"
#include "models/gyroscope_units.h"

namespace accelcal {

using GyroscopeRandomEffects = std::array<RandomEffectsEstimate, kGyroscopeCalibrationCount>;

// by_parameter[i][s]: unknown i of the 12 (kGyroscopeCalibrationCount's order) in session s.
std::vector<std::vector<SessionEstimate>> GyroscopeSessionEstimates(
    const std::vector<GyroscopeMlResult>& sessions);

// Every unknown's random-effects estimate from the device's own sessions (2 or more).
Status CombineGyroscopeSessions(const std::vector<GyroscopeMlResult>& sessions, double confidence,
                                GyroscopeRandomEffects* combined);

struct GyroscopeSessionsOptions {
  // Every session's options but its start, which `initial_gain` gives.
  GyroscopeSessionOptions session;
  // The gains' start, (rad/s) per unit; 0: the unit's nominal gain, which counts do not have
  // (their sessions are then not calibrated, and say why).
  double initial_gain = 0.0;
};

// One session's gyroscope: calibrated, or why not.
struct GyroscopeSessionOutcome {
  bool present = false;  // the log has gyroscope samples
  int samples = 0;
  bool calibrated = false;
  std::string not_calibrated;  // why not, in words (present or not)
  GyroscopeSessionCalibration calibration;
};

// The session's gyroscope on `accelerometer`'s poses and fit; never fails: a refusal is the
// outcome's reason.
GyroscopeSessionOutcome CalibrateSessionGyroscope(const TriadLog& log,
                                                  const TriadSessionCalibration& accelerometer,
                                                  const GyroscopeSessionsOptions& options);

struct GyroscopeSessionsResult {
  std::vector<int> sessions;  // the sessions combined (indices), those calibrated
  bool combined = false;
  std::string not_combined;  // why, when not
  GyroscopeRandomEffects random_effects{};
  SessionDriftCheck drift;  // over the sessions combined (drift.sessions[i].session indexes them)
};

// The calibrated sessions' random effects and drift check at `drift_level`; fails only when
// the combination's input is unusable (a non-finite estimate).
Status CombineGyroscopeSessionOutcomes(const std::vector<GyroscopeSessionOutcome>& outcomes,
                                       double confidence, double drift_level,
                                       GyroscopeSessionsResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_SESSIONS_H_
