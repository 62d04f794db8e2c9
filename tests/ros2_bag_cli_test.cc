// calibrate_imu on a ROS 2 bag, end to end (issue 34, item 4): a hand-held session simulated
// here (simulation/triad_log_simulator.h: rests, turns, a gyroscope), written both as a bag of
// sensor_msgs/msg/Imu messages (tests/ros2_bag_writer.h) and as a CSV of the very same numbers,
// calibrates to the same result in modes imu_tk and ml; the bag's files are in the provenance;
// topic choices and damaged bags are refused with exit status 2, one line, nothing written.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/format.h"
#include "ros2_bag_writer.h"
#include "simulation/random.h"
#include "simulation/triad_log_simulator.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::BagTopic;
using testing::CommandResult;
using testing::ExpectBadInputContract;
using testing::RunBinaryArgs;
using testing::ScratchDir;

constexpr int32_t kStartSec = 1700000000;  // the header stamps: a Unix time, as drivers write

// An IMU that reports in SI units, as ROS drivers do (REP 145): gains near 1, small offsets and
// angles, 0.01 m/s^2 and 0.002 rad/s of noise, not quantised; 100 Hz, a rest of 30 s, then 24
// poses of 3 s in random directions, turned about gravity too so the gyroscope sees every axis.
TriadLog SimulateSiSession() {
  TriadLogSimulationOptions options;
  options.truth = TriadParametersWithOffset(0.05, -0.08, 0.12);
  options.truth[kTriadGainX] = 1.01;
  options.truth[kTriadGainY] = 0.99;
  options.truth[kTriadGainZ] = 1.005;
  options.truth[0] = 0.002;
  options.truth[1] = -0.003;
  options.truth[2] = 0.001;
  options.noise_stddev = {0.01, 0.01, 0.01};
  options.round_to_counts = false;
  options.gyroscope.enabled = true;
  options.gyroscope.truth = GyroscopeParametersWithGain(1.02, 0.98, 1.01);
  options.gyroscope.offset = {0.01, -0.02, 0.005};
  options.gyroscope.noise_stddev = {0.002, 0.002, 0.002};
  options.gyroscope.round_to_counts = false;
  RandomSource random(34);
  std::vector<TriadHold> holds = {{{0.0, 0.0, 1.0}, 30.0}};
  for (TriadHold hold : RandomSeparatedHolds(24, 3.0, 30.0, &random)) {
    hold.turn_yaw_deg = 40.0;
    holds.push_back(hold);
  }
  return SimulateTriadSession(options, holds, &random).log;
}

// The header stamps' times as the bag's reader computes them: whole ns from the first stamp.
double StampTime(double t_s) { return static_cast<double>(std::llround(t_s * 1e9)) * 1e-9; }

// The same samples as CSV, every number written to round-trip exactly.
std::string Csv(const TriadLog& log) {
  std::string text = "t_s,ax,ay,az,gx,gy,gz\n";
  for (size_t i = 0; i < log.size(); ++i) {
    text +=
        StringPrintf("%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", StampTime(log.timestamp_s[i]),
                     log.output[i][0], log.output[i][1], log.output[i][2], log.gyroscope[i][0],
                     log.gyroscope[i][1], log.gyroscope[i][2]);
  }
  return text;
}

// A bag folder as ros2 bag record writes it: metadata.yaml and NAME_0.db3.
std::string WriteBagFolder(const ScratchDir& scratch, const std::string& name,
                           const std::vector<BagTopic>& topics) {
  const std::string folder = scratch.File(name);
  EXPECT_EQ(mkdir(folder.c_str(), 0755), 0);
  EXPECT_EQ(testing::WriteBagFile(folder + "/" + name + "_0.db3", topics), "");
  scratch.Write(name + "/metadata.yaml", testing::BagMetadataYaml({name + "_0.db3"}));
  return folder;
}

// The simulated session's Imu topic, named `name`.
BagTopic SessionTopic(const TriadLog& log, const std::string& name) {
  BagTopic topic{name};
  topic.messages = testing::ImuMessages(log, kStartSec);
  return topic;
}

// The JSON of a run without what names its input: the provenance (files, command line) and the
// log's description (its path, layout and reading notes).
nlohmann::json WithoutInputDescription(nlohmann::json json) {
  for (const char* key : {"input_files", "command_line", "log"}) json.erase(key);
  return json;
}

CommandResult Calibrate(const std::string& log, const std::string& mode, const std::string& json,
                        const std::vector<std::string>& more = {}) {
  std::vector<std::string> args = {"--log=" + log, "--mode=" + mode, "--init_rest_s=30",
                                   "--json=" + json};
  args.insert(args.end(), more.begin(), more.end());
  return RunBinaryArgs("calibrate_imu", args);
}

// The "done when": the bag and the CSV of the same samples give the same calibration,
// every parameter, sigma, covariance, verdict and gyroscope figure identical. The bag's units
// come from the message type (REP 145), the CSV's from the flags.
TEST(Ros2BagCli, ABagCalibratesToTheResultOfTheCsvOfTheSameSamplesInBothModes) {
  ScratchDir scratch;
  const TriadLog log = SimulateSiSession();
  const BagTopic imu = SessionTopic(log, "/imu/data");
  BagTopic status{"/diagnostics", "diagnostic_msgs/msg/DiagnosticArray"};
  status.messages = {{int64_t{kStartSec} * 1000000000 + 5, "not an Imu"}};
  const std::string bag = WriteBagFolder(scratch, "session", {imu, status});
  const std::string csv = scratch.Write("session.csv", Csv(log));
  for (const std::string mode : {"imu_tk", "ml"}) {
    SCOPED_TRACE(mode);
    const CommandResult from_bag = Calibrate(bag, mode, scratch.File(mode + "_bag.json"));
    ASSERT_EQ(from_bag.exit_status, 0) << from_bag.stderr_text;
    const CommandResult from_csv = Calibrate(csv, mode, scratch.File(mode + "_csv.json"),
                                             {"--unit=m/s^2", "--gyro_unit=rad/s"});
    ASSERT_EQ(from_csv.exit_status, 0) << from_csv.stderr_text;
    const nlohmann::json bag_json =
        nlohmann::json::parse(testing::ReadText(scratch.File(mode + "_bag.json")));
    const nlohmann::json csv_json =
        nlohmann::json::parse(testing::ReadText(scratch.File(mode + "_csv.json")));
    ASSERT_TRUE(bag_json.contains("parameters"));
    ASSERT_TRUE(bag_json.contains("gyroscope"));  // the angular velocities were calibrated too
    EXPECT_EQ(bag_json["parameters"], csv_json["parameters"]);
    const nlohmann::json differences =
        nlohmann::json::diff(WithoutInputDescription(csv_json), WithoutInputDescription(bag_json));
    EXPECT_TRUE(differences.empty())
        << "first differences (CSV -> bag): " << differences.dump().substr(0, 2000);
    // The provenance covers the bag's files: its .db3 by checksum, and its metadata.yaml.
    EXPECT_EQ(bag_json["input_files"]["log"]["path"], bag + "/session_0.db3");
    EXPECT_EQ(bag_json["input_files"]["log"]["bytes"],
              testing::ReadText(bag + "/session_0.db3").size());
    EXPECT_EQ(bag_json["input_files"]["log_metadata"]["path"], bag + "/metadata.yaml");
    EXPECT_NE(from_bag.stdout_text.find("topic /imu/data read: the bag's one sensor_msgs/msg/Imu "
                                        "topic"),
              std::string::npos);
    EXPECT_NE(from_bag.stdout_text.find("outputs in m/s^2, as sensor_msgs/msg/Imu (REP 145) says"),
              std::string::npos);
  }
  // The .db3 file given by itself: the same result.
  const CommandResult from_file =
      Calibrate(bag + "/session_0.db3", "ml", scratch.File("file.json"));
  ASSERT_EQ(from_file.exit_status, 0) << from_file.stderr_text;
  EXPECT_TRUE(nlohmann::json::diff(WithoutInputDescription(nlohmann::json::parse(
                                       testing::ReadText(scratch.File("file.json")))),
                                   WithoutInputDescription(nlohmann::json::parse(
                                       testing::ReadText(scratch.File("ml_csv.json")))))
                  .empty());
}

// The lines of a corrected CSV that are not '#' comments (which name the input files).
std::string DataLines(const std::string& text) {
  std::string data;
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = std::min(text.find('\n', begin), text.size());
    if (text[begin] != '#') data += text.substr(begin, end - begin + 1);
    begin = end + 1;
  }
  return data;
}

// apply and allan read bags through the same reader, and cover the bag's files in their
// provenance: apply corrects the bag's samples to exactly the CSV's corrected values.
TEST(Ros2BagCli, ApplyCorrectsTheBagAsTheCsvAndAllanReadsIt) {
  ScratchDir scratch;
  const TriadLog log = SimulateSiSession();
  const std::string bag = WriteBagFolder(scratch, "session", {SessionTopic(log, "/imu/data")});
  const std::string csv = scratch.Write("session.csv", Csv(log));
  const std::string calibration = scratch.File("calibration.json");
  ASSERT_EQ(Calibrate(bag, "ml", scratch.File("ml.json"), {"--calibration_out=" + calibration})
                .exit_status,
            0);
  const CommandResult from_bag = RunBinaryArgs(
      "apply", {"--calibration=" + calibration, "--in=" + bag, "--out=" + scratch.File("bag.csv")});
  ASSERT_EQ(from_bag.exit_status, 0) << from_bag.stderr_text;
  const CommandResult from_csv = RunBinaryArgs(
      "apply", {"--calibration=" + calibration, "--in=" + csv, "--out=" + scratch.File("csv.csv")});
  ASSERT_EQ(from_csv.exit_status, 0) << from_csv.stderr_text;
  const std::string corrected = DataLines(testing::ReadText(scratch.File("bag.csv")));
  EXPECT_GT(corrected.size(), 1000u);
  EXPECT_EQ(corrected, DataLines(testing::ReadText(scratch.File("csv.csv"))));
  EXPECT_NE(testing::ReadText(scratch.File("bag.csv")).find("session_0.db3 (sha256 "),
            std::string::npos);
  const CommandResult allan = RunBinaryArgs("allan", {"--log=" + bag});
  EXPECT_EQ(allan.exit_status, 0) << allan.stderr_text;
  EXPECT_NE(allan.stdout_text.find("session_0.db3"), std::string::npos);
}

// Refused in one line, exit status 2, nothing on stdout and no output written.
void ExpectRefused(const std::string& log, const std::vector<std::string>& more,
                   const std::string& fragment) {
  ScratchDir out;
  std::vector<std::string> args = {"--log=" + log, "--mode=ml", "--json=" + out.File("out.json")};
  args.insert(args.end(), more.begin(), more.end());
  ExpectBadInputContract(RunBinaryArgs("calibrate_imu", args), "calibrate_imu", fragment);
  struct stat info;
  EXPECT_NE(stat(out.File("out.json").c_str(), &info), 0) << "written: " << out.File("out.json");
}

TEST(Ros2BagCli, TheTopicIsChosenOrRefusedNamingTheCandidatesAndTheFlag) {
  ScratchDir scratch;
  const TriadLog log = SimulateSiSession();
  BagTopic left{"/left/imu"}, right{"/right/imu"};
  BagTopic odometry{"/odom", "nav_msgs/msg/Odometry"};
  left.messages = testing::ImuMessages(log, kStartSec);
  right.messages = testing::ImuMessages(log, kStartSec, 3000000);
  const std::string two = WriteBagFolder(scratch, "two", {left, right, odometry});
  ExpectRefused(two, {},
                "2 sensor_msgs/msg/Imu topics (/left/imu, /right/imu): name one with "
                "--topic=/left/imu");
  ExpectRefused(two, {"--topic=/odom"}, "--topic=/odom is of type nav_msgs/msg/Odometry");
  const std::string none = WriteBagFolder(scratch, "none", {odometry});
  ExpectRefused(
      none, {},
      "no sensor_msgs/msg/Imu topic in the bag; its topics: /odom (nav_msgs/msg/Odometry)");
  const CommandResult chosen =
      RunBinaryArgs("calibrate_imu", {"--log=" + two, "--mode=ml", "--topic=/right/imu"});
  EXPECT_EQ(chosen.exit_status, 0) << chosen.stderr_text;
  EXPECT_NE(chosen.stdout_text.find("topic /right/imu"), std::string::npos);
}

TEST(Ros2BagCli, DamagedBagsExitWithStatusTwoInOneLineAndWriteNothing) {
  ScratchDir scratch;
  const TriadLog log = SimulateSiSession();
  const BagTopic imu = SessionTopic(log, "/imu");
  const std::string good = WriteBagFolder(scratch, "good", {imu});
  const std::string bytes = testing::ReadText(good + "/good_0.db3");
  // Truncated, as a copy cut short: the header states more pages than the file holds.
  const std::string cut = WriteBagFolder(scratch, "cut", {imu});
  scratch.Write("cut/cut_0.db3", bytes.substr(0, bytes.size() * 2 / 3));
  ExpectRefused(cut, {}, cut + "/cut_0.db3: the file is cut short");
  // One message cut short.
  BagTopic short_message = imu;
  short_message.messages[5000].data.resize(60);
  const std::string shortened = WriteBagFolder(scratch, "short", {short_message});
  ExpectRefused(shortened, {}, "message id 5001 (topic /imu): the message is cut short");
  // A topic that says Imu but holds another message (a std_msgs/msg/String's bytes).
  BagTopic strings{"/imu"};
  strings.messages = {{1, std::string("\0\x01\0\0\x06\0\0\0hello\0\0\0", 16)}};
  ExpectRefused(WriteBagFolder(scratch, "wrong", {strings}), {},
                "the bag is damaged, or the topic is not sensor_msgs/msg/Imu");
  // Not SQLite at all, under a .db3 name inside a bag folder.
  const std::string text = WriteBagFolder(scratch, "text", {imu});
  scratch.Write("text/text_0.db3", "t,ax,ay,az\n0,1,2,3\n");
  ExpectRefused(text, {}, "not an SQLite database");
  // Stamps that repeat.
  BagTopic repeated = imu;
  TriadLog stale = log;
  stale.timestamp_s[3000] = stale.timestamp_s[2999];
  repeated.messages = testing::ImuMessages(stale, kStartSec);
  ExpectRefused(WriteBagFolder(scratch, "stale", {repeated}), {},
                "does not increase from the previous message's");
  // MCAP.
  ExpectRefused(scratch.Write("bag.mcap", std::string("\x89MCAP0\r\n", 8) + "x"), {},
                "ros2 bag convert");
}

}  // namespace
}  // namespace accelcal
