// calibrate_imu --log=S1,S2,... (several sessions of one device) and triad_repeatability end
// to end on mimu4444: the table and JSON keys (docs/json.md, calibrate_imu_sessions), the refusals
// (one line, exit status 2, nothing written), and the leave-one-session-out figures as printed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

// --- The gyroscope (issue 44, item 8) ---

std::string Imu1GyroscopeRuns(const std::string& dir) {
  return dir + "/run1/imu1_acc_gyr.csv," + dir + "/run2/imu1_acc_gyr.csv," + dir +
         "/run3/imu1_acc_gyr.csv";
}

constexpr char kMimuGyroGain[] = " --initial_gyro_gain=0.00106422515";

TEST(CalibrateImuSessionsCli, GyroscopeColumnsGiveTheGyroscopesNewSessionSigma) {
  REQUIRE_MIMU4444(dir);
  testing::ScratchDir scratch;
  const std::string json_path = scratch.File("sessions.json");
  const testing::CommandResult result =
      RunBinary("calibrate_imu", "--log='" + Imu1GyroscopeRuns(dir) + "' --g=9.8187 --mode=ml" +
                                     kMimuGyroGain + " --json=" + json_path);
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::string& out = result.stdout_text;
  EXPECT_NE(out.find("  gyroscope: 37439 samples, 19 turns"), std::string::npos) << out;
  EXPECT_NE(out.find("  combined over sessions 1 2 3\n"), std::string::npos) << out;
  EXPECT_NE(out.find("\n  gyroscope_offset_x  "), std::string::npos) << out;
  EXPECT_NE(out.find("Drift (gyroscope): each session against the others"), std::string::npos)
      << out;
  EXPECT_NE(out.find("Drift (accelerometer): each session against the others"), std::string::npos)
      << out;

  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  // The accelerometer's keys as without the gyroscope.
  EXPECT_NEAR(json["stddev_new_session"]["offset_z"].get<double>(), 3.45, 0.01);
  const nlohmann::json& gyroscope = json["gyroscope"];
  ASSERT_TRUE(gyroscope.is_object()) << json.dump();
  EXPECT_EQ(gyroscope["output_unit"], "count");
  EXPECT_EQ(gyroscope["sessions_combined"], nlohmann::json({1, 2, 3}));
  EXPECT_TRUE(gyroscope["not_combined"].is_null());
  ASSERT_EQ(gyroscope["parameters"].size(), 12u);
  // The common value is a weighted mean of the sessions' (within their range); a new session's
  // sigma holds at least one session's own; the 95% multiplier is t_2(0.975).
  double lowest = HUGE_VAL, highest = -HUGE_VAL, within = 0.0;
  for (int s = 0; s < 3; ++s) {
    const nlohmann::json& own = json["sessions"][s]["gyroscope"];
    const double value = own["parameters"]["gyroscope_offset_x"].get<double>();
    lowest = std::min(lowest, value);
    highest = std::max(highest, value);
    within = std::max(within, own["stddev"]["gyroscope_offset_x"].get<double>());
  }
  const double common = gyroscope["parameters"]["gyroscope_offset_x"].get<double>();
  EXPECT_GE(common, lowest);
  EXPECT_LE(common, highest);
  EXPECT_GE(gyroscope["stddev_new_session"]["gyroscope_offset_x"].get<double>(), within);
  EXPECT_NEAR(gyroscope["interval_multiplier_95"]["gyroscope_gain_z"].get<double>(), 4.303, 0.001);
  EXPECT_EQ(gyroscope["units"]["gyroscope_gain_x"], "(rad/s)/count");
  EXPECT_EQ(gyroscope["degrees_of_freedom"], 2);
  EXPECT_EQ(gyroscope["drift"]["checked"], true);
  EXPECT_EQ(gyroscope["drift"]["parameter_count"], 12);
  EXPECT_EQ(gyroscope["drift"]["sessions"].size(), 3u);
  EXPECT_EQ(json["drift"]["parameter_count"], 9);
  // Each session's own gyroscope, the 12-unknown model every session shares: the single-session
  // mode's, or its baseline when discovery extended that session's model (issue 44, item 7).
  EXPECT_EQ(json["sessions"][0]["gyroscope"]["calibrated"], true);
  const std::string single_path = scratch.File("single.json");
  const testing::CommandResult single =
      RunBinary("calibrate_imu", "--log=" + dir + "/run1/imu1_acc_gyr.csv --g=9.8187 --mode=ml" +
                                     kMimuGyroGain + " --json=" + single_path);
  ASSERT_EQ(single.exit_status, 0) << single.stderr_text;
  const nlohmann::json alone = nlohmann::json::parse(testing::ReadText(single_path));
  const nlohmann::json& own = alone["gyroscope"]["baseline"].is_object()
                                  ? alone["gyroscope"]["baseline"]
                                  : alone["gyroscope"];
  EXPECT_NEAR(json["sessions"][0]["gyroscope"]["parameters"]["gyroscope_offset_x"].get<double>(),
              own["parameters"]["gyroscope_offset_x"].get<double>(), 1e-6);
}

// A session without a gyroscope among sessions with one: named, and left out of the
// gyroscope's combination (never dropped silently); the accelerometer combines all three.
TEST(CalibrateImuSessionsCli, NamesASessionWithoutAGyroscope) {
  REQUIRE_MIMU4444(dir);
  testing::ScratchDir scratch;
  const std::string json_path = scratch.File("sessions.json");
  const std::string logs =
      dir + "/run1/imu1_acc_gyr.csv," + dir + "/run2/imu1.csv," + dir + "/run3/imu1_acc_gyr.csv";
  const testing::CommandResult result =
      RunBinary("calibrate_imu", "--log='" + logs + "' --g=9.8187 --mode=ml" + kMimuGyroGain +
                                     " --json=" + json_path);
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::string& out = result.stdout_text;
  EXPECT_NE(out.find("  gyroscope: none in this log: not calibrated\n"), std::string::npos) << out;
  EXPECT_NE(out.find("  combined over sessions 1 3; LEFT OUT: session 2"), std::string::npos)
      << out;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  EXPECT_EQ(json["gyroscope"]["sessions_combined"], nlohmann::json({1, 3}));
  ASSERT_EQ(json["gyroscope"]["sessions_left_out"].size(), 1u);
  EXPECT_EQ(json["gyroscope"]["sessions_left_out"][0]["session"], 2);
  EXPECT_EQ(json["gyroscope"]["degrees_of_freedom"], 1);
  EXPECT_EQ(json["gyroscope"]["drift"]["checked"], false);
  EXPECT_EQ(json["degrees_of_freedom"], 2);
  EXPECT_EQ(json["sessions"][1]["gyroscope"]["present"], false);
}

// Gyroscope columns in counts without a gain to start from: each session says so, nothing is
// combined; logs without any gyroscope give no gyroscope lines at all (as before).
TEST(CalibrateImuSessionsCli, SaysPerSessionWhyTheGyroscopeIsNotCalibrated) {
  REQUIRE_MIMU4444(dir);
  testing::ScratchDir scratch;
  const std::string json_path = scratch.File("sessions.json");
  testing::CommandResult result =
      RunBinary("calibrate_imu",
                "--log='" + Imu1GyroscopeRuns(dir) + "' --g=9.8187 --mode=ml --json=" + json_path);
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  size_t lines = 0;
  for (size_t at = result.stdout_text.find("NOT calibrated: its outputs are counts");
       at != std::string::npos;
       at = result.stdout_text.find("NOT calibrated: its outputs are counts", at + 1))
    ++lines;
  EXPECT_EQ(lines, 3u) << result.stdout_text;
  EXPECT_NE(result.stdout_text.find("  not combined: 0 of 3 sessions' gyroscopes calibrated"),
            std::string::npos)
      << result.stdout_text;
  nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  EXPECT_TRUE(json["gyroscope"]["parameters"].is_null());

  result = RunBinary("calibrate_imu",
                     "--log='" + Imu1Runs(dir) + "' --g=9.8187 --mode=ml --json=" + json_path);
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_EQ(result.stdout_text.find("yroscope"), std::string::npos) << result.stdout_text;
  json = nlohmann::json::parse(testing::ReadText(json_path));
  EXPECT_TRUE(json["gyroscope"].is_null());
}

TEST(CalibrateImuSessionsCli, RefusesGyroscopeFlagsItCannotUse) {
  REQUIRE_MIMU4444(dir);
  testing::ScratchDir scratch;
  ExpectRefused("--mode=ml --log='" + Imu1Runs(dir) + "'" + kMimuGyroGain,
                "no session's log has one", scratch);
  ExpectRefused(
      "--mode=ml --log='" + Imu1Runs(dir) + "' --gyro_log='" + dir + "/run1/imu1_acc_gyr.csv'",
      "--gyro_log names 1 gyroscope file(s) for 3 sessions", scratch);
  ExpectRefused("--mode=ml --log='" + Imu1GyroscopeRuns(dir) + "' --gyro_bias=rest",
                "--gyro_bias belongs to --mode=imu_tk", scratch);
  ExpectRefused("--mode=ml --log='" + Imu1GyroscopeRuns(dir) + "' --initial_gyro_gain=0",
                "--initial_gyro_gain=0 is not a gain", scratch);
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
