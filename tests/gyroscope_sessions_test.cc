// Repeatability of the gyroscope across sessions (issue 44, item 8; estimation/gyroscope/
// gyroscope_sessions.h, studies/gyroscope_repeatability.h): which session drifts
// (CheckSessionDrift), the new-session sigma's coverage on simulated sessions of known spread,
// and the leave-one-session-out check on mimu4444 runs 1-3 with the gyroscope.

#include "estimation/gyroscope/gyroscope_sessions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "estimation/triad/triad_sessions.h"
#include "io/imu_log.h"
#include "simulation/random.h"
#include "studies/gyroscope_repeatability.h"
#include "studies/triad_repeatability.h"
#include "test_support.h"

namespace accelcal {
namespace {

// Sessions of P parameters, theta = mu + N(0, tau^2) + N(0, C).
std::vector<std::vector<SessionEstimate>> DrawSessions(int parameters, int sessions, double tau,
                                                       double within, RandomSource* random) {
  std::vector<std::vector<SessionEstimate>> by_parameter(parameters);
  for (std::vector<SessionEstimate>& estimates : by_parameter) {
    for (int s = 0; s < sessions; ++s) {
      estimates.push_back(
          {10.0 + tau * random->StandardNormal() + std::sqrt(within) * random->StandardNormal(),
           within});
    }
  }
  return by_parameter;
}

// A session whose parameter jumps by 40 tau among 6 sessions is named, with that parameter alone;
// sessions drawn alike are named at most at the stated level (5% per sensor: Bonferroni over
// its 12 parameters), within 3 binomial sd over 2000 draws of 6 sessions.
TEST(SessionDrift, NamesTheSessionThatJumpsAndKeepsItsLevel) {
  RandomSource random(21);
  std::vector<std::vector<SessionEstimate>> sessions = DrawSessions(12, 6, 1.0, 0.01, &random);
  sessions[10][3].value += 40.0;
  SessionDriftCheck check;
  ASSERT_TRUE(CheckSessionDrift(sessions, 0.05, &check).ok());
  ASSERT_TRUE(check.checked);
  EXPECT_NEAR(check.parameter_level, 0.05 / 12, 1e-15);
  EXPECT_EQ(check.degrees_of_freedom, 4.0);
  // Session 4 (index 3) is named for its offset; another session may be named by chance (at
  // most 5% each).
  ASSERT_TRUE(check.sessions[3].drifting());
  EXPECT_NE(std::find(check.drifting.begin(), check.drifting.end(), 3), check.drifting.end());
  ASSERT_EQ(check.sessions[3].outside.size(), 1u);
  EXPECT_EQ(check.sessions[3].outside[0].parameter, 10);
  EXPECT_EQ(check.sessions[3].largest.parameter, 10);
  EXPECT_GT(check.sessions[3].largest.deviation, check.multiplier);

  constexpr int kDraws = 2000;
  int named = 0, session_checks = 0;
  for (int draw = 0; draw < kDraws; ++draw) {
    ASSERT_TRUE(CheckSessionDrift(DrawSessions(12, 6, 1.0, 0.01, &random), 0.05, &check).ok());
    named += static_cast<int>(check.drifting.size());
    session_checks += static_cast<int>(check.sessions.size());
  }
  const double rate = static_cast<double>(named) / session_checks;
  EXPECT_LE(rate, 0.05 + 3.0 * std::sqrt(0.05 * 0.95 / kDraws)) << named << "/" << session_checks;
  EXPECT_GT(rate, 0.0);  // not a rule that never names anything

  // Two sessions: nothing to leave one out against, said so.
  ASSERT_TRUE(CheckSessionDrift(DrawSessions(12, 2, 1.0, 0.01, &random), 0.05, &check).ok());
  EXPECT_FALSE(check.checked);
  EXPECT_NE(check.not_checked.find("3 sessions"), std::string::npos) << check.not_checked;
}

// Through the simulator and the sessions path (the noise-floor detector, the accelerometer's
// session calibration, the gyroscope's as calibrate_imu --mode=ml calibrates it): 60 devices,
// 3 sessions learnt and a 4th predicted, every gyroscope unknown moving between sessions by 5
// times its within-session sigma. The new session falls inside common +- t_2 x
// stddev_new_session 95% of the time within 3 binomial sd over the 720 predictions (0.8%), and
// every kind at least 95% less 3 sd of its own count. Measured (seed 1, 60 devices): 684/720
// (95.0%); misalignments 341/360, gains 168/180, offsets 175/180. The Q-profile interval of tau
// covers the simulated tau 92.4% (printed, not claimed here).
TEST(GyroscopeRepeatability, NewSessionIntervalCoversNinetyFivePercent) {
  GyroscopeRepeatabilityOptions options;
  options.devices = 60;
  options.training_sessions = 3;
  GyroscopeRepeatabilityResult result;
  const Status status = RunGyroscopeRepeatabilityMonteCarlo(options, &result);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(result.failed_devices, 0) << result.first_failure;
  const CoverageCount& all = result.coverage_all;
  ASSERT_EQ(all.total, 60 * kGyroscopeCalibrationCount);
  std::cout << "gyroscope new-session coverage: " << all.covered << "/" << all.total << " = "
            << all.fraction() << " (standard error " << result.coverage_standard_error
            << "); tau interval " << result.tau_interval_coverage.fraction() << "\n";
  for (int kind = 0; kind < kTriadParameterKindCount; ++kind) {
    const CoverageCount& count = result.coverage[kind];
    std::cout << "  " << TriadParameterKindName(static_cast<TriadParameterKind>(kind)) << " "
              << count.covered << "/" << count.total << "\n";
    EXPECT_GE(count.fraction(), 0.95 - 3.0 * std::sqrt(0.95 * 0.05 / count.total)) << kind;
  }
  EXPECT_NEAR(all.fraction(), 0.95, 3.0 * result.coverage_standard_error);
}

// --- mimu4444 runs 1-3 with the gyroscope (imu<k>_acc_gyr.csv, 1/16.4 deg/s per count) ---

std::string Mimu4444Dir() {
  return testing::DataDirFrom("ACCELCAL_MIMU4444_DATA", ACCELCAL_DEFAULT_MIMU4444_DATA,
                              "run3/imu8_acc_gyr.csv");
}

// Every IMU's gyroscope in every run, as calibrate_imu --log=... --initial_gyro_gain calibrates
// each session; then each run left out in turn for every IMU and unknown (8 x 3 x 12 = 288
// cases): is the left-out run inside the other two's new-session 95% interval? Issue 44's target
// is 90% in the device scheme (each IMU's own tau, what calibrate_imu reports). Measured on the
// gyroscope noise model of 2026-12 (before the noise-model work in progress): device 285/288
// (99.0%), pooled over the 8 IMUs 256/288 (88.9%), array 268/288 (93.1%).
TEST(Mimu4444, GyroscopeLeaveOneSessionOutCoversTheTarget) {
  const std::string dir = Mimu4444Dir();
  if (dir.empty()) GTEST_SKIP() << "mimu4444 data not found: set ACCELCAL_MIMU4444_DATA";
  TriadSessionOptions accelerometer;
  accelerometer.gravity_mps2 = 9.8187;
  GyroscopeSessionsOptions gyroscope;
  gyroscope.session.gravity_mps2 = 9.8187;
  gyroscope.initial_gain = 0.00106422515;
  std::vector<std::vector<GyroscopeMlResult>> sessions(8);
  for (int run = 1; run <= 3; ++run) {
    for (int imu = 1; imu <= 8; ++imu) {
      const std::string path =
          dir + "/run" + std::to_string(run) + "/imu" + std::to_string(imu) + "_acc_gyr.csv";
      TriadLog log;
      ASSERT_TRUE(ReadImuLog(path, &log).ok()) << path;
      TriadSessionCalibration calibration;
      const Status status = CalibrateTriadSession(log, accelerometer, &calibration);
      ASSERT_TRUE(status.ok()) << path << ": " << status.message();
      const GyroscopeSessionOutcome outcome =
          CalibrateSessionGyroscope(log, calibration, gyroscope);
      ASSERT_TRUE(outcome.calibrated) << path << ": " << outcome.not_calibrated;
      sessions[imu - 1].push_back(outcome.calibration.ml);
    }
  }
  LosoResult loso;
  ASSERT_TRUE(
      LeaveOneSessionOutOf(GyroscopeArrayEstimates(sessions), GyroscopeParameterKinds(), &loso)
          .ok());
  CoverageCount schemes[kSessionSchemeCount];
  for (const SessionPrediction& prediction : loso.predictions) {
    CoverageCount& count = schemes[static_cast<int>(prediction.scheme)];
    ++count.total;
    count.covered += prediction.covered;
  }
  for (int scheme = 0; scheme < kSessionSchemeCount; ++scheme) {
    std::cout << "mimu4444 gyroscope leave-one-session-out, "
              << SessionSchemeName(static_cast<SessionScheme>(scheme)) << ": "
              << schemes[scheme].covered << "/" << schemes[scheme].total << " = "
              << schemes[scheme].fraction() << "\n";
  }
  const CoverageCount& device = schemes[static_cast<int>(SessionScheme::kDevice)];
  EXPECT_EQ(device.total, 8 * 3 * kGyroscopeCalibrationCount);
  EXPECT_GE(device.fraction(), 0.90) << device.covered << "/" << device.total;
}

}  // namespace
}  // namespace accelcal
