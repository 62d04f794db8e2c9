// calibrate_imu --log=S1,S2,... (several sessions of one device) and triad_repeatability end
// to end on mimu4444: the table and JSON keys (docs/json_sessions.md), the refusals (one line,
// exit status 2, nothing written), and the leave-one-session-out figures as printed.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::ExpectBadInputContract;
using testing::RunBinary;

std::string Mimu4444Dir() {
  return testing::DataDirFrom("ACCELCAL_MIMU4444_DATA", ACCELCAL_DEFAULT_MIMU4444_DATA,
                              "run3/imu8.csv");
}

#define REQUIRE_MIMU4444(dir)            \
  const std::string dir = Mimu4444Dir(); \
  if (dir.empty()) GTEST_SKIP() << "mimu4444 data not found: set ACCELCAL_MIMU4444_DATA"

std::string Imu1Runs(const std::string& dir) {
  return dir + "/run1/imu1.csv," + dir + "/run2/imu1.csv," + dir + "/run3/imu1.csv";
}

TEST(CalibrateImuSessionsCli, ThreeRunsOfImu1GiveEverySigmaByName) {
  REQUIRE_MIMU4444(dir);
  testing::ScratchDir scratch;
  const std::string json_path = scratch.File("sessions.json");
  const testing::CommandResult result = RunBinary(
      "calibrate_imu", "--log='" + Imu1Runs(dir) + "' --g=9.8187 --mode=ml --json=" + json_path);
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::string& out = result.stdout_text;
  EXPECT_NE(out.find("3 sessions of one device combined"), std::string::npos) << out;
  EXPECT_NE(out.find("t_2(0.975) = 4.3"), std::string::npos) << out;
  EXPECT_NE(out.find("WITHIN-session sigma"), std::string::npos) << out;

  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  EXPECT_EQ(json["mode"], "ml_sessions");
  ASSERT_EQ(json["sessions"].size(), 3u);
  EXPECT_EQ(json["sessions"][0]["poses"], 20);
  EXPECT_EQ(json["sessions"][1]["poses"], 21);
  EXPECT_NEAR(json["sessions"][0]["parameters"]["offset_x"].get<double>(), -57.688, 0.001);
  EXPECT_NEAR(json["sessions"][0]["stddev"]["offset_x"].get<double>(), 0.082, 0.001);
  EXPECT_EQ(json["sessions"][0]["sha256"], json["input_files"]["session_1"]["sha256"]);
  EXPECT_NEAR(json["parameters"]["offset_x"].get<double>(), -59.01, 0.01);
  EXPECT_NEAR(json["stddev"]["offset_x"].get<double>(), 0.082, 0.001);
  EXPECT_NEAR(json["between_session_stddev"]["offset_x"].get<double>(), 1.21, 0.01);
  EXPECT_NEAR(json["stddev_new_session"]["offset_z"].get<double>(), 3.45, 0.01);
  EXPECT_NEAR(json["interval_multiplier_95"]["gain_x"].get<double>(), 4.303, 0.001);
  EXPECT_EQ(json["units"]["offset_z"], "count");
  EXPECT_EQ(json["degrees_of_freedom"], 2);
  for (const char* key : {"source", "input_files", "command_line", "accelcal_version"})
    EXPECT_TRUE(json.contains(key)) << key;
}

void ExpectRefused(const std::string& arguments, const std::string& fragment,
                   const testing::ScratchDir& scratch) {
  const std::string json_path = scratch.File("never.json");
  const testing::CommandResult result =
      RunBinary("calibrate_imu", arguments + " --g=9.8187 --json=" + json_path);
  ExpectBadInputContract(result, "calibrate_imu", fragment);
  EXPECT_FALSE(testing::PathExists(json_path)) << arguments;
}

TEST(CalibrateImuSessionsCli, RefusesWhatCannotBeCombined) {
  REQUIRE_MIMU4444(dir);
  testing::ScratchDir scratch;
  const std::string a = dir + "/run1/imu1.csv", b = dir + "/run2/imu1.csv";
  ExpectRefused("--mode=ml --log='" + a + ",'", "ends with a comma", scratch);
  ExpectRefused("--mode=ml --log='" + a + "," + a + "'", "twice", scratch);
  ExpectRefused("--mode=imu_tk --log='" + a + "," + b + "'", "needs --mode=ml", scratch);
  ExpectRefused("--mode=ml --detector=imu_tk --log='" + a + "," + b + "'",
                "--detector=noise_floor only", scratch);

  // The same recording under two names.
  const std::string copy = scratch.File("copy.csv");
  std::ofstream(copy) << testing::ReadText(a);
  ExpectRefused("--mode=ml --log='" + a + "," + copy + "'", "holds the same bytes as", scratch);

  // A session converted to m/s^2 beside one in counts.
  std::istringstream lines(testing::ReadText(b));
  std::ostringstream converted;
  std::string line;
  std::getline(lines, line);
  converted << line << "\n";
  while (std::getline(lines, line)) {
    double t, x, y, z;
    char comma;
    std::istringstream(line) >> t >> comma >> x >> comma >> y >> comma >> z;
    converted << t << "," << x * 0.00479 << "," << y * 0.00479 << "," << z * 0.00479 << "\n";
  }
  const std::string mps2 = scratch.Write("mps2.csv", converted.str());
  ExpectRefused("--mode=ml --log='" + a + "," + mps2 + "'", "the sessions hold different units",
                scratch);

  // A session too short to calibrate (its first 2000 samples: a few poses), named.
  std::istringstream head(testing::ReadText(b));
  std::ostringstream short_log;
  for (int i = 0; i < 2001 && std::getline(head, line); ++i) short_log << line << "\n";
  const std::string cut = scratch.Write("cut.csv", short_log.str());
  ExpectRefused("--mode=ml --log='" + a + "," + cut + "'",
                "session 2 (" + cut + ") fails calibration", scratch);
}

TEST(TriadRepeatabilityCli, PrintsTheLeaveOneSessionOutCoverage) {
  REQUIRE_MIMU4444(dir);
  testing::ScratchDir scratch;
  const std::string json_path = scratch.File("repeatability.json");
  const testing::CommandResult result =
      RunBinary("triad_repeatability", "--data_dir='" + dir + "' --trials=0 --json=" + json_path);
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::string& out = result.stdout_text;
  EXPECT_NE(out.find("8 devices x 3 sessions"), std::string::npos) << out;
  EXPECT_NE(out.find("  device        72/72  100.0%      72/72  100.0%      72/72  100.0%"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("  array         67/72   93.1%      68/72   94.4%      72/72  100.0%"),
            std::string::npos)
      << out;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  EXPECT_EQ(json["leave_one_session_out"]["coverage"]["pooled"]["offset"]["covered"], 62);
  EXPECT_EQ(json["per_device"].size(), 8u);
  EXPECT_TRUE(json.contains("input_files"));
}

}  // namespace
}  // namespace accelcal
