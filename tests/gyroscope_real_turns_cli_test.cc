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
#include <functional>
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
      "calibrate_imu", {"--log=" + dir + "/run" + std::to_string(run) + "/imu" +
                            std::to_string(imu) + "_acc_gyr.csv",
                        "--mode=ml", "--initial_gyro_gain=0.00106422515",
                        std::string("--gyro_turn_sampling=") + (sampling ? "true" : "false"),
                        "--json=" + json_path});
  EXPECT_EQ(result.exit_status, 0) << result.stderr_text;
  return nlohmann::json::parse(testing::ReadText(json_path))["gyroscope"];
}

// `text` (a mimu4444 CSV: t_s, 3 accelerometer, 3 gyroscope columns) with each row's gyroscope
// field k replaced by edit(k, field).
std::string WithGyroscopeFields(const std::string& text,
                                const std::function<std::string(int, const std::string&)>& edit) {
  std::string edited;
  size_t start = 0;
  bool header = true;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    if (line.empty()) continue;
    if (header) {
      edited += line + "\n";
      header = false;
      continue;
    }
    std::vector<std::string> fields;
    size_t field_start = 0;
    while (true) {
      const size_t comma = line.find(',', field_start);
      fields.push_back(line.substr(field_start, comma - field_start));
      if (comma == std::string::npos) break;
      field_start = comma + 1;
    }
    EXPECT_EQ(fields.size(), 7u) << line;
    for (size_t k = 4; k < fields.size() && k < 7; ++k) fields[k] = edit(k - 4, fields[k]);
    for (size_t f = 0; f < fields.size(); ++f) edited += (f ? "," : "") + fields[f];
    edited += "\n";
  }
  return edited;
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

// The gyroscope's unit and start gain against the turns (issue 45: outputs in the wrong unit
// ended in a calibration in that unit, "missing" and exit 0, the turns' sampling error absorbing
// the misses). mimu4444's outputs are counts of 1/16.4 deg/s: told they are deg/s, or (converted
// to deg/s by the test) told they are rad/s, or counts with a start gain 16 times too large,
// calibrate_imu refuses in one line naming the factor and the flags; the flags it names then
// calibrate the session (exit 0).
TEST(GyroscopeRealTurns, OutputsInAnotherUnitThanGivenAreRefusedWithFlagsThatWork) {
  const std::string dir = Mimu4444Dir();
  if (dir.empty()) GTEST_SKIP() << "mimu4444 data not found: set ACCELCAL_MIMU4444_DATA";
  testing::ScratchDir scratch;
  const std::string counts = dir + "/run1/imu1_acc_gyr.csv";
  // The same session with its gyroscope in deg/s.
  const std::string converted = WithGyroscopeFields(
      testing::ReadText(counts),
      [](int, const std::string& field) { return std::to_string(std::stod(field) / 16.4); });
  const std::string degrees = scratch.Write("imu1_deg_s.csv", converted);

  struct Case {
    std::string log;
    std::vector<std::string> flags;
    std::string expected_advice;
  };
  const Case cases[] = {
      {counts, {"--gyro_unit=deg/s"}, "--gyro_unit=count --initial_gyro_gain="},
      {counts, {"--initial_gyro_gain=0.0174533"}, "--gyro_unit=count --initial_gyro_gain="},
      {degrees, {"--gyro_unit=rad/s"}, "--gyro_unit=deg/s"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"--log=" + c.log, "--mode=ml"};
    args.insert(args.end(), c.flags.begin(), c.flags.end());
    const testing::CommandResult refused = testing::RunBinaryArgs("calibrate_imu", args);
    EXPECT_EQ(refused.exit_status, 2) << c.flags[0] << ": " << refused.stdout_text.substr(0, 400);
    const std::string& message = refused.stderr_text;
    EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << message;
    const size_t at = message.find("give " + c.expected_advice);
    ASSERT_NE(at, std::string::npos) << c.flags[0] << ": " << message;
    // The flags it names, in place of those given.
    std::string advice = message.substr(at + 5);
    while (!advice.empty() && (advice.back() == '\n' || advice.back() == ' ')) advice.pop_back();
    std::vector<std::string> again = {"--log=" + c.log, "--mode=ml",
                                      "--json=" + scratch.File("again.json")};
    size_t start = 0;
    while (start < advice.size()) {
      size_t space = advice.find(' ', start);
      if (space == std::string::npos) space = advice.size();
      again.push_back(advice.substr(start, space - start));
      start = space + 1;
    }
    const testing::CommandResult calibrated = testing::RunBinaryArgs("calibrate_imu", again);
    EXPECT_EQ(calibrated.exit_status, 0) << advice << ": " << calibrated.stderr_text;
    if (c.log == counts && calibrated.exit_status == 0) {
      // The gain it suggested is the sensor's (1/16.4 deg/s per count) within 2%.
      const nlohmann::json g =
          nlohmann::json::parse(testing::ReadText(scratch.File("again.json")))["gyroscope"];
      EXPECT_NEAR(g["parameters"]["gyroscope_gain_x"].get<double>(), 0.00106422515,
                  0.02 * 0.00106422515);
    }
  }
}

// A gyroscope channel that reads the same value in every sample (here mimu4444 run 1 IMU 1 with
// its y column zeroed) is named as dead, disconnected, stuck or the wrong column (issue 45: it was
// "the 0 turns between the 20 poses do not determine ...", every turn taken as clipped at a rail).
TEST(GyroscopeRealTurns, ADeadChannelIsNamedAsOne) {
  const std::string dir = Mimu4444Dir();
  if (dir.empty()) GTEST_SKIP() << "mimu4444 data not found: set ACCELCAL_MIMU4444_DATA";
  testing::ScratchDir scratch;
  const std::string dead = WithGyroscopeFields(
      testing::ReadText(dir + "/run1/imu1_acc_gyr.csv"),
      [](int k, const std::string& field) { return k == 1 ? std::string("0") : field; });
  const std::string path = scratch.Write("dead_y.csv", dead);
  const testing::CommandResult result = testing::RunBinaryArgs(
      "calibrate_imu", {"--log=" + path, "--mode=ml", "--initial_gyro_gain=0.00106422515"});
  EXPECT_EQ(result.exit_status, 2);
  EXPECT_NE(result.stderr_text.find("the gyroscope's y output is 0 in every one of the log's"),
            std::string::npos)
      << result.stderr_text;
  EXPECT_NE(result.stderr_text.find("dead, disconnected or stuck channel"), std::string::npos);
}

}  // namespace
}  // namespace accelcal
