// Host receive times in bursts, end to end (issue 44, item 4): a simulated hand-held session
// with a gyroscope, its samples stamped as a BLE link delivers them (bursts of 2 to 20, 0.2 ms
// apart, the device clock 200 ppm fast, a few samples lost), written with and without a
// sample-number column. calibrate_imu times them by the index at a fitted rate and agrees with
// the calibration from the true sample times within the parameters' sigma; without an index it
// refuses, and the flag it names works; apply and allan read the log as it does.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/format.h"
#include "host_burst_log.h"
#include "studies/gyroscope_monte_carlo.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::HostBurstTimes;
using testing::RunBinaryArgs;

constexpr double kDriftPpm = 200.0;

// One simulated session, the samples the link kept, and their stamps.
struct BurstSession {
  TriadLog log;
  HostBurstTimes times;
};

const BurstSession& Session() {
  static const BurstSession* session = [] {
    GyroscopeSessionDesign design;
    GyroscopeSessionFit fit;
    EXPECT_TRUE(SimulateAndCalibrateGyroscope(design, GyroscopeDesignHolds(design, 21), 22, {},
                                              &fit)
                    .ok());
    auto* made = new BurstSession;
    made->log = fit.session.log;
    made->times = testing::SimulateHostBursts(static_cast<int>(made->log.size()), 100.0,
                                              kDriftPpm, 5, 23);
    return made;
  }();
  return *session;
}

// The session's kept samples as CSV: time (the true sample times, or the host's stamps), an
// index column named `index_name` (none when null), the accelerometer, the gyroscope.
std::string WriteSession(const testing::ScratchDir& scratch, const std::string& name,
                         bool true_times, const char* index_name, bool gyroscope = true) {
  const BurstSession& session = Session();
  std::string text = std::string(true_times ? "t" : "host_time_us") +
                     (index_name ? std::string(",") + index_name : std::string()) + ",ax,ay,az" +
                     (gyroscope ? ",gx,gy,gz" : "") + "\n";
  for (size_t j = 0; j < session.times.index.size(); ++j) {
    const size_t i = static_cast<size_t>(session.times.index[j]);
    const auto& a = session.log.output[i];
    const auto& g = session.log.gyroscope[i];
    text += true_times ? RoundTripDouble(session.times.true_s[j])
                       : std::to_string(session.times.host_us[j]);
    if (index_name) text += "," + std::to_string(session.times.index[j]);
    text += StringPrintf(",%.0f,%.0f,%.0f", a[0], a[1], a[2]);
    if (gyroscope) text += StringPrintf(",%.0f,%.0f,%.0f", g[0], g[1], g[2]);
    text += "\n";
  }
  return scratch.Write(name, text);
}

std::vector<std::string> CalibrateArgs(const std::string& log, const std::string& json) {
  return {"--log=" + log, "--mode=ml", "--g=9.81744", "--gyro_unit=count",
          "--initial_gyro_gain=0.00021", "--json=" + json};
}

nlohmann::json Calibrate(const std::vector<std::string>& args, const std::string& json_path,
                         std::string* stdout_text = nullptr) {
  const testing::CommandResult run = RunBinaryArgs("calibrate_imu", args);
  EXPECT_EQ(run.exit_status, 0) << run.stderr_text;
  if (stdout_text != nullptr) *stdout_text = run.stdout_text;
  if (run.exit_status != 0) return nlohmann::json();
  return nlohmann::json::parse(testing::ReadText(json_path));
}

// Every parameter of `block` (its "parameters" and "stddev") within `sigmas` of the reference's.
void ExpectAgreement(const nlohmann::json& block, const nlohmann::json& reference,
                     const char* what, double sigmas) {
  double largest = 0.0;
  for (const auto& [name, value] : reference.at("parameters").items()) {
    const double sigma = reference.at("stddev").at(name).get<double>();
    const double shift = std::abs(block.at("parameters").at(name).get<double>() -
                                  value.get<double>()) / sigma;
    largest = std::max(largest, shift);
    EXPECT_LT(shift, sigmas) << what << " " << name;
  }
  std::cout << what << ": largest shift from the true times' calibration " << largest
            << " sigma\n";
}

TEST(HostTimeBurstsCli, TheIndexTimesTheSamplesAsTheTrueTimesDo) {
  testing::ScratchDir scratch;
  const nlohmann::json truth = Calibrate(
      CalibrateArgs(WriteSession(scratch, "true.csv", true, nullptr), scratch.File("true.json")),
      scratch.File("true.json"));
  std::string printed;
  const nlohmann::json fitted =
      Calibrate(CalibrateArgs(WriteSession(scratch, "ble.csv", false, "idx"),
                              scratch.File("ble.json")),
                scratch.File("ble.json"), &printed);
  ASSERT_FALSE(truth.is_null());
  ASSERT_FALSE(fitted.is_null());
  ExpectAgreement(fitted, truth, "accelerometer", 0.3);
  ExpectAgreement(fitted.at("gyroscope"), truth.at("gyroscope"), "gyroscope", 0.3);
  const nlohmann::json& time = fitted.at("log").at("time");
  std::cout << "log.time: " << time.dump() << "\n";
  EXPECT_EQ(time.at("from"), "sample number and a fitted rate");
  EXPECT_EQ(time.at("index_column"), "'idx'");
  EXPECT_EQ(time.at("dropped_samples"), 5);
  EXPECT_EQ(time.at("nominal_rate_hz"), 100.0);
  const double true_rate_hz = 100.0 * (1.0 + 1e-6 * kDriftPpm);
  EXPECT_LE(std::abs(time.at("fitted_rate_hz").get<double>() - true_rate_hz),
            time.at("fitted_rate_tolerance_hz").get<double>());
  EXPECT_GT(time.at("host_time_bursts").at("share_below_third_period").get<double>(), 0.2);
  EXPECT_EQ(truth.at("log").at("time").at("from"), "time column");
  EXPECT_TRUE(truth.at("log").at("time").at("host_time_bursts").is_null());
  // Said where the log is described.
  const size_t read = printed.find("  read: time: host receive times in bursts in 'host_time_us'");
  EXPECT_NE(read, std::string::npos) << printed;
  EXPECT_NE(printed.find("sample times from the index 'idx' at a fitted", read), std::string::npos);
}

TEST(HostTimeBurstsCli, WithoutAnIndexEveryReaderRefusesAndTheNamedFlagsWork) {
  testing::ScratchDir scratch;
  const std::string plain = WriteSession(scratch, "plain.csv", false, nullptr);
  const std::string json = scratch.File("out.json");
  const testing::CommandResult refused = RunBinaryArgs("calibrate_imu", CalibrateArgs(plain, json));
  testing::ExpectBadInputContract(refused, "calibrate_imu",
                                  "time 'host_time_us': the time stamps come in bursts (");
  std::cout << refused.stderr_text;
  EXPECT_TRUE(testing::FilesIn(scratch.path()).size() == 1) << "nothing written";
  const std::string& message = refused.stderr_text;
  const size_t at = message.find("--rate_hz=");
  ASSERT_NE(at, std::string::npos) << message;
  const std::string rate_flag = message.substr(at, message.find_first_of(", ", at) - at);
  std::vector<std::string> followed = CalibrateArgs(plain, json);
  followed.push_back(rate_flag);
  EXPECT_FALSE(Calibrate(followed, json).is_null()) << rate_flag;

  // An unnamed counter: --columns=index:NAME, as the message says.
  const std::string counted = WriteSession(scratch, "counted.csv", false, "pkt");
  testing::ExpectBadInputContract(RunBinaryArgs("calibrate_imu", CalibrateArgs(counted, json)),
                                  "calibrate_imu", "--columns=index:NAME");
  followed = CalibrateArgs(counted, json);
  followed.push_back("--columns=index:pkt");
  EXPECT_EQ(Calibrate(followed, json).at("log").at("time").at("from"),
            "sample number and a fitted rate");

  // allan and apply read the log as calibrate_imu does, streamed or not.
  for (const char* stream : {"--stream=true", "--stream=false"}) {
    testing::ExpectBadInputContract(
        RunBinaryArgs("allan", {"--log=" + plain, "--unit=count", stream}), "allan",
        "the time stamps come in bursts");
  }
  const std::string calibration = scratch.File("calibration.json");
  followed = CalibrateArgs(WriteSession(scratch, "ble.csv", false, "idx"), json);
  followed.push_back("--calibration_out=" + calibration);
  ASSERT_FALSE(Calibrate(followed, json).is_null());
  for (const char* stream : {"--stream=true", "--stream=false"}) {
    testing::ExpectBadInputContract(
        RunBinaryArgs("apply", {"--calibration=" + calibration, "--in=" + plain,
                                "--out=" + scratch.File("refused.csv"), stream}),
        "apply", "the time stamps come in bursts");
    const std::string out = scratch.File(std::string("corrected") + stream + ".csv");
    const testing::CommandResult applied =
        RunBinaryArgs("apply", {"--calibration=" + calibration, "--in=" + scratch.File("ble.csv"),
                                "--out=" + out, stream});
    EXPECT_EQ(applied.exit_status, 0) << applied.stderr_text;
    EXPECT_NE(applied.stderr_text.find("sample times from the index 'idx'"), std::string::npos)
        << applied.stderr_text;
  }
  // The same rows either way (the header's command line names the flag).
  const auto rows = [&](const char* stream) {
    const std::string text = testing::ReadText(scratch.File(std::string("corrected") + stream +
                                                            ".csv"));
    return text.substr(text.find("\nt_s,"));
  };
  EXPECT_EQ(rows("--stream=true"), rows("--stream=false"));
}

TEST(HostTimeBurstsCli, AnAccelerometerOnlyLogIsTimedAndRefusedAlike) {
  testing::ScratchDir scratch;
  const std::string json = scratch.File("out.json");
  const std::vector<std::string> args = {"--mode=ml", "--g=9.81744", "--json=" + json};
  std::vector<std::string> run = args;
  run.push_back("--log=" + WriteSession(scratch, "plain.csv", false, nullptr, false));
  testing::ExpectBadInputContract(RunBinaryArgs("calibrate_imu", run), "calibrate_imu",
                                  "the time stamps come in bursts");
  run = args;
  run.push_back("--log=" + WriteSession(scratch, "indexed.csv", false, "idx", false));
  const nlohmann::json fitted = Calibrate(run, json);
  ASSERT_FALSE(fitted.is_null());
  EXPECT_EQ(fitted.at("log").at("time").at("from"), "sample number and a fitted rate");
  EXPECT_EQ(fitted.at("log").at("gyroscope_samples"), 0);
}

}  // namespace
}  // namespace accelcal
