// The gyroscope on real sessions (issue 44, item 1): the mimu4444 array's 24 sessions (runs 1-3,
// IMUs 1-8, ../shared/data/mimu4444 or ACCELCAL_MIMU4444_DATA), turned by hand at 62.5 Hz.
// Their turns miss by far more than the white noise and wander allow (chi2/dof 4 to 45), in
// proportion to how abruptly the rate changes between samples: the turns' sampling error
// (docs/gyroscope.md). With it in the noise model every session's gyroscope is explained by the
// model and its noise (no "unexplained"), kappa is about the same in every session (a property
// of the sensor's sampling, not of the session), and the angles' and gains' scatter between the
// three sessions of each IMU is about their sigma (it was 3 to 6 times it).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_support.h"

namespace accelcal {
namespace {

std::string Mimu4444Dir() {
  return testing::DataDirFrom("ACCELCAL_MIMU4444_DATA", ACCELCAL_DEFAULT_MIMU4444_DATA,
                              "run3/imu8_acc_gyr.csv");
}

nlohmann::json CalibrateSession(const std::string& dir, int run, int imu, bool sampling,
                                const testing::ScratchDir& scratch) {
  const std::string json_path =
      scratch.File("r" + std::to_string(run) + "i" + std::to_string(imu) + ".json");
  const testing::CommandResult result = testing::RunBinaryArgs(
      "calibrate_imu",
      {"--log=" + dir + "/run" + std::to_string(run) + "/imu" + std::to_string(imu) +
           "_acc_gyr.csv",
       "--mode=ml", "--initial_gyro_gain=0.00106422515",
       std::string("--gyro_turn_sampling=") + (sampling ? "true" : "false"), "--json=" + json_path});
  EXPECT_EQ(result.exit_status, 0) << result.stderr_text;
  return nlohmann::json::parse(testing::ReadText(json_path))["gyroscope"];
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// Per parameter of the 9 (angles and gains), over the 8 IMUs: the sd of the 3 sessions'
// estimates over their rms sigma; the median over IMUs and parameters.
double MedianScatterOverSigma(const std::vector<std::vector<nlohmann::json>>& by_imu) {
  std::vector<double> ratios;
  for (const std::vector<nlohmann::json>& sessions : by_imu) {
    const nlohmann::json& order = sessions[0]["parameter_order"];
    for (int i = 0; i < 9; ++i) {
      const std::string name = order[i];
      double mean = 0.0, variance = 0.0, sigma2 = 0.0;
      for (const nlohmann::json& g : sessions) mean += g["parameters"][name].get<double>() / 3.0;
      for (const nlohmann::json& g : sessions) {
        const double d = g["parameters"][name].get<double>() - mean;
        variance += d * d / 2.0;
        sigma2 += std::pow(g["stddev"][name].get<double>(), 2) / 3.0;
      }
      ratios.push_back(std::sqrt(variance / sigma2));
    }
  }
  return Median(ratios);
}

TEST(GyroscopeRealTurns, TheSamplingErrorExplainsTheMimu4444TurnsAndItsSigmaHoldsBetweenSessions) {
  const std::string dir = Mimu4444Dir();
  if (dir.empty()) GTEST_SKIP() << "mimu4444 data not found: set ACCELCAL_MIMU4444_DATA";
  testing::ScratchDir scratch;
  std::vector<std::vector<nlohmann::json>> by_imu(8);
  std::vector<double> kappas;
  for (int imu = 1; imu <= 8; ++imu) {
    for (int run = 1; run <= 3; ++run) {
      const nlohmann::json g = CalibrateSession(dir, run, imu, true, scratch);
      ASSERT_TRUE(g.is_object());
      const std::string where = "run " + std::to_string(run) + ", IMU " + std::to_string(imu);
      const nlohmann::json& discovery = g["discovery"];
      EXPECT_NE(discovery["verdict"], "unexplained") << where << ": " << discovery["verdict_text"];
      EXPECT_TRUE(discovery["turn_sampling"].get<bool>()) << where;
      const double kappa = std::sqrt(g["turn_sampling_variance"].get<double>());
      kappas.push_back(kappa);
      // The turn 100 s long that ends in the saturating motion after the poses is left out as
      // clipped (it was fitted, off by 1.3 to 2.2 rad).
      for (const nlohmann::json& turn : g["turns"])
        EXPECT_LT(turn["residual_angle_rad"].get<double>(), 0.1) << where;
      by_imu[imu - 1].push_back(g);
    }
  }
  // One property of the sensor's sampling: measured 0.13 to 0.19 over the 24 sessions.
  EXPECT_GT(*std::min_element(kappas.begin(), kappas.end()), 0.08);
  EXPECT_LT(*std::max_element(kappas.begin(), kappas.end()), 0.3);
  // Measured: 1.3 (median over 8 IMUs x 9 parameters); 4.0 without the sampling error. The
  // sample sd of 3 sessions over a right sigma has median 0.83.
  EXPECT_LT(MedianScatterOverSigma(by_imu), 2.0);
}

// Without the term (--gyro_turn_sampling=false, as before), the same turns are unexplained: the
// test above fails on such a model (its scatter ratio measured 4.0 over the 24 sessions; here
// IMU 1's three sessions).
TEST(GyroscopeRealTurns, WithoutTheSamplingErrorTheTurnsAreUnexplained) {
  const std::string dir = Mimu4444Dir();
  if (dir.empty()) GTEST_SKIP() << "mimu4444 data not found: set ACCELCAL_MIMU4444_DATA";
  testing::ScratchDir scratch;
  for (int run = 1; run <= 3; ++run) {
    const nlohmann::json g = CalibrateSession(dir, run, 1, false, scratch);
    ASSERT_TRUE(g.is_object());
    EXPECT_EQ(g["discovery"]["verdict"], "unexplained") << g["discovery"]["verdict_text"];
    EXPECT_EQ(g["turn_sampling_variance"].get<double>(), 0.0);
  }
}

}  // namespace
}  // namespace accelcal
