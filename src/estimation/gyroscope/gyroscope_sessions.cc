#include "estimation/gyroscope/gyroscope_sessions.h"

#include "common/format.h"

namespace accelcal {

std::vector<std::vector<SessionEstimate>> GyroscopeSessionEstimates(
    const std::vector<GyroscopeMlResult>& sessions) {
  std::vector<std::vector<SessionEstimate>> by_parameter(kGyroscopeCalibrationCount);
  for (const GyroscopeMlResult& ml : sessions) {
    for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
      const double value =
          i < kGyroscopeOffsetX ? ml.parameters[i] : ml.offset[i - kGyroscopeOffsetX];
      by_parameter[i].push_back({value, ml.covariance(i, i)});
    }
  }
  return by_parameter;
}

Status CombineGyroscopeSessions(const std::vector<GyroscopeMlResult>& sessions, double confidence,
                                GyroscopeRandomEffects* combined) {
  const std::vector<std::vector<SessionEstimate>> by_parameter =
      GyroscopeSessionEstimates(sessions);
  for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
    ACCELCAL_RETURN_IF_ERROR(EstimateRandomEffects(by_parameter[i], confidence, &(*combined)[i])
                                 .WithContext(GyroscopeCalibrationParameterName(i)));
  }
  return Status::Ok();
}

GyroscopeSessionOutcome CalibrateSessionGyroscope(const TriadLog& log,
                                                  const TriadSessionCalibration& accelerometer,
                                                  const GyroscopeSessionsOptions& options) {
  GyroscopeSessionOutcome outcome;
  outcome.present = log.has_gyroscope();
  outcome.samples = static_cast<int>(log.gyroscope.size());
  if (!outcome.present) {
    outcome.not_calibrated = "the log has no gyroscope";
    return outcome;
  }
  double gain = options.initial_gain;
  if (!(gain > 0.0)) gain = GyroscopeNominalGain(options.session.unit);
  if (!(gain > 0.0)) {
    outcome.not_calibrated =
        "its outputs are counts and its calibration needs their gain to start from; give "
        "--initial_gyro_gain=G in (rad/s) per count (G = 1/S for a datasheet sensitivity S in "
        "counts per rad/s), or --gyro_unit=rad/s or deg/s";
    return outcome;
  }
  GyroscopeSessionOptions session = options.session;
  session.initial = GyroscopeParametersWithGain(gain, gain, gain);
  Status status =
      CalibrateGyroscopeSession(log, accelerometer.pose_intervals, accelerometer.ml_options,
                                accelerometer.ml, session, &outcome.calibration);
  if (status.ok()) {
    status = CheckGyroscopeMatchesUnit(outcome.calibration.ml.parameters,
                                       outcome.calibration.ml.offset, options.session.unit);
  }
  if (!status.ok()) {
    outcome.not_calibrated = "its calibration refused: " + status.message();
    return outcome;
  }
  outcome.calibrated = true;
  return outcome;
}

Status CombineGyroscopeSessionOutcomes(const std::vector<GyroscopeSessionOutcome>& outcomes,
                                       double confidence, double drift_level,
                                       GyroscopeSessionsResult* result) {
  *result = GyroscopeSessionsResult();
  std::vector<GyroscopeMlResult> calibrated;
  for (size_t s = 0; s < outcomes.size(); ++s) {
    if (!outcomes[s].calibrated) continue;
    result->sessions.push_back(static_cast<int>(s));
    calibrated.push_back(outcomes[s].calibration.ml);
  }
  if (calibrated.size() < 2) {
    result->not_combined = StringPrintf(
        "%zu of %zu sessions' gyroscopes calibrated; a between-session sigma needs at least 2",
        calibrated.size(), outcomes.size());
    return Status::Ok();
  }
  ACCELCAL_RETURN_IF_ERROR(CombineGyroscopeSessions(calibrated, confidence, &result->random_effects)
                               .WithContext("the gyroscope"));
  ACCELCAL_RETURN_IF_ERROR(
      CheckSessionDrift(GyroscopeSessionEstimates(calibrated), drift_level, &result->drift)
          .WithContext("the gyroscope"));
  result->combined = true;
  return Status::Ok();
}

}  // namespace accelcal
