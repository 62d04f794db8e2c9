#ifndef ACCELCAL_REPORTING_TRIAD_SESSIONS_REPORT_H_
#define ACCELCAL_REPORTING_TRIAD_SESSIONS_REPORT_H_

// What `calibrate_imu --log=S1,S2,... --mode=ml` prints and writes (docs/repeatability.md,
// docs/json.md, calibrate_imu_sessions), and what triad_repeatability prints and writes. Each
// figure says which sigma it is: `stddev` (within-session: one session's own ceres::Covariance, the
// mean over the sessions), `between_session_stddev` (tau, how much the device itself moves between
// sessions), `stddev_new_session` (what a new session's estimate scatters about the common
// value). Formatting only.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "estimation/gyroscope/gyroscope_sessions.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "estimation/triad/triad_sessions.h"
#include "models/triad_units.h"
#include "studies/triad_repeatability.h"

namespace accelcal {

struct TriadSessionReport {
  std::string path;
  std::string sha256;
  TriadSessionCalibration calibration;
  // The gyroscope's own file (--gyro_log's item) and its checksum, when it came from one.
  std::string gyroscope_path;
  std::string gyroscope_sha256;
  GyroscopeSessionOutcome gyroscope;
};

struct TriadSessionsReport {
  TriadSessionOptions options;  // every session's
  std::vector<TriadSessionReport> sessions;
  TriadRandomEffects combined{};
  SessionDriftCheck drift;  // the accelerometer's
  // Some session's log has a gyroscope: then every session says what became of its gyroscope,
  // and the gyroscope's combination follows the accelerometer's.
  bool has_gyroscope = false;
  GyroscopeSessionsOptions gyroscope_options;
  GyroscopeSessionsResult gyroscope;
};

std::string TriadSessionsTable(const TriadSessionsReport& report);
nlohmann::json TriadSessionsJson(const TriadSessionsReport& report);

// triad_repeatability: sessions[d][s] of an array's devices, named.
struct TriadRepeatabilityReport {
  double gravity_mps2 = 9.81;
  std::vector<std::string> device_names;   // e.g. imu1
  std::vector<std::string> session_names;  // e.g. run1
  std::vector<std::vector<TriadMlResult>> sessions;
  std::vector<TriadRandomEffects> per_device;  // each device's own, all sessions
  std::array<ArraySessionVariance, kTriadParameterCount> array{};
  LosoResult loso;
  // The gyroscope, when the logs have one (--log_suffix, --initial_gyro_gain): every device's
  // sessions' outcomes, each device's combination, and the leave-one-session-out check over
  // the devices whose every session's gyroscope calibrated (gyroscope_devices, indices).
  bool has_gyroscope = false;
  GyroscopeOutputUnit gyroscope_unit = GyroscopeOutputUnit::kCount;
  std::vector<std::vector<GyroscopeSessionOutcome>> gyroscope_sessions;  // [d][s]
  std::vector<GyroscopeSessionsResult> gyroscope_per_device;
  std::vector<int> gyroscope_devices;
  bool has_gyroscope_loso = false;
  std::string gyroscope_loso_not_run;  // why, when not
  LosoResult gyroscope_loso;
  bool has_monte_carlo = false;
  RepeatabilityMonteCarloResult monte_carlo;
};

std::string TriadRepeatabilityTable(const TriadRepeatabilityReport& report);
nlohmann::json TriadRepeatabilityJson(const TriadRepeatabilityReport& report);
std::string RepeatabilityMonteCarloTable(const RepeatabilityMonteCarloResult& result);
nlohmann::json RepeatabilityMonteCarloJson(const RepeatabilityMonteCarloResult& result);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_TRIAD_SESSIONS_REPORT_H_
