// ROS 2 bags (issue 34, item 4): sensor_msgs/msg/Imu's CDR decoding (io/ros2_imu_message.h) and
// the sqlite3 storage's reading (io/ros2_bag.h) through ReadImuLog, on bags written here
// (tests/ros2_bag_writer.h): the log equals the messages, the topic is chosen or refused by the
// rules, and damaged bags are refused in one line naming the file.

#include "io/ros2_bag.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "io/imu_log.h"
#include "io/input_file.h"
#include "io/ros2_imu_message.h"
#include "ros2_bag_writer.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::BagMessage;
using testing::BagTopic;
using testing::ScratchDir;

Ros2ImuMessage ExampleMessage() {
  Ros2ImuMessage message;
  message.stamp_sec = 1700000000;
  message.stamp_nanosec = 123456789;
  message.frame_id = "imu_link";
  message.orientation = {0.1, 0.2, 0.3, 0.9};
  for (int k = 0; k < 9; ++k) {
    message.orientation_covariance[k] = 0.01 * k;
    message.angular_velocity_covariance[k] = 0.02 * k;
    message.linear_acceleration_covariance[k] = 0.03 * k;
  }
  message.angular_velocity_radps = {0.01, -0.02, 1.5};
  message.linear_acceleration_mps2 = {0.1, -9.8, 0.25};
  return message;
}

TEST(Ros2ImuMessage, DecodesWhatItEncodesInBothByteOrders) {
  for (bool big_endian : {false, true}) {
    const std::string data = EncodeRos2ImuMessage(ExampleMessage(), big_endian);
    // 4 (encapsulation) + 8 (stamp) + 4 + 9 ("imu_link" and NUL), padded to 24, + 37 * 8.
    EXPECT_EQ(data.size(), 4u + 24u + 37u * 8u);
    EXPECT_EQ(data[1], big_endian ? '\0' : '\x01');
    Ros2ImuMessage decoded;
    ASSERT_TRUE(DecodeRos2ImuMessage(data, &decoded).ok());
    EXPECT_EQ(decoded.stamp_sec, 1700000000);
    EXPECT_EQ(decoded.stamp_nanosec, 123456789u);
    EXPECT_EQ(decoded.frame_id, "imu_link");
    EXPECT_EQ(decoded.orientation, ExampleMessage().orientation);
    EXPECT_EQ(decoded.linear_acceleration_covariance,
              ExampleMessage().linear_acceleration_covariance);
    EXPECT_EQ(decoded.angular_velocity_radps, ExampleMessage().angular_velocity_radps);
    EXPECT_EQ(decoded.linear_acceleration_mps2, ExampleMessage().linear_acceleration_mps2);
  }
}

// The bytes of a known message, written out by hand from the CDR rules (not by the encoder):
// the stamp, frame_id "imu0" (length 5 with its NUL), padding to the next multiple of 8 (24:
// a float64's alignment is 8 in CDR version 1, 4 in XCDR2's), then 37 doubles.
TEST(Ros2ImuMessage, ReadsTheFieldsWhereCdrPutsThem) {
  std::string data = {'\0', '\x01', '\0', '\0'};
  auto u32 = [&data](uint32_t v) {
    for (int i = 0; i < 4; ++i) data.push_back(static_cast<char>(v >> (8 * i)));
  };
  auto f64 = [&data](double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, 8);
    for (int i = 0; i < 8; ++i) data.push_back(static_cast<char>(bits >> (8 * i)));
  };
  u32(5);
  u32(7);
  u32(5);
  data.append("imu0", 5);
  data.append(7, '\0');  // 17 bytes after the header, padded to 24
  for (int i = 0; i < 37; ++i) f64(i);
  Ros2ImuMessage message;
  ASSERT_TRUE(DecodeRos2ImuMessage(data, &message).ok());
  EXPECT_EQ(message.StampNs(), 5000000007);
  EXPECT_EQ(message.frame_id, "imu0");
  EXPECT_EQ(message.angular_velocity_radps, (std::array<double, 3>{13, 14, 15}));
  EXPECT_EQ(message.linear_acceleration_mps2, (std::array<double, 3>{25, 26, 27}));
  EXPECT_EQ(message.linear_acceleration_covariance[8], 36);
}

TEST(Ros2ImuMessage, RefusesEveryCutAndDamagedLengthsWithoutReadingPastTheEnd) {
  const std::string data = EncodeRos2ImuMessage(ExampleMessage());
  for (size_t size = 0; size < data.size(); ++size) {
    Ros2ImuMessage message;
    const Status status = DecodeRos2ImuMessage(std::string_view(data.data(), size), &message);
    EXPECT_FALSE(status.ok()) << size;
    EXPECT_NE(status.message().find("cut short"), std::string::npos) << status.message();
  }
  std::string long_string = data;
  long_string[13] = '\x7f';  // frame_id's length: 9 + 127 * 256, past the end
  Ros2ImuMessage message;
  EXPECT_ERROR_CONTAINS(DecodeRos2ImuMessage(long_string, &message),
                        "header.frame_id needs 32521 bytes");
  std::string xcdr2 = data;
  xcdr2[1] = '\x07';
  EXPECT_ERROR_CONTAINS(DecodeRos2ImuMessage(xcdr2, &message), "is not CDR version 1");
  EXPECT_ERROR_CONTAINS(DecodeRos2ImuMessage(data + std::string(16, '\0'), &message),
                        "the message is of another type");
  Ros2ImuMessage nan = ExampleMessage();
  nan.linear_acceleration_mps2[1] = std::nan("");
  EXPECT_ERROR_CONTAINS(DecodeRos2ImuMessage(EncodeRos2ImuMessage(nan), &message),
                        "not a finite number");
}

// A 100 Hz log of `count` samples with a gyroscope, values that tell the samples apart.
TriadLog ExampleLog(int count) {
  TriadLog log;
  for (int i = 0; i < count; ++i) {
    log.Add(0.01 * i, 0.001 * i, -9.81 + 1e-4 * i, 0.5);
    log.gyroscope.push_back({1e-3 * i, -2e-3, 3e-3});
  }
  return log;
}

// An accelerometer-only driver's bag (angular_velocity 0, angular_velocity_covariance[0] = -1 in
// every message, sensor_msgs/msg/Imu's "no data") reads as a log without a gyroscope, said in a
// note (issue 45: it was read as a gyroscope at rest, and its calibration refused); one message
// with rates keeps the gyroscope.
TEST(Ros2Bag, AnAccelerometerOnlyDriversBagHasNoGyroscope) {
  ScratchDir scratch;
  TriadLog written = ExampleLog(200);
  written.gyroscope.clear();
  BagTopic imu{"/imu/data"};
  imu.messages = testing::ImuMessages(written, 1700000000);
  const std::string path = scratch.File("accelerometer_only.db3");
  ASSERT_EQ(testing::WriteBagFile(path, {imu}), "");
  TriadLog log;
  ImuLogSource source;
  ASSERT_TRUE(ReadImuLog(path, ImuLogReadOptions(), &log, ImuLogSpacing::kEven, &source).ok());
  EXPECT_EQ(log.size(), 200u);
  EXPECT_FALSE(log.has_gyroscope());
  bool said = false;
  for (const std::string& note : source.notes)
    said = said || note.find("angular_velocity_covariance[0] is -1") != std::string::npos;
  EXPECT_TRUE(said);
  // One message with rates: a gyroscope.
  Ros2ImuMessage with_rates;
  ASSERT_TRUE(DecodeRos2ImuMessage(imu.messages[7].data, &with_rates).ok());
  with_rates.angular_velocity_covariance[0] = 0.0;
  imu.messages[7].data = EncodeRos2ImuMessage(with_rates);
  const std::string mixed = scratch.File("mixed.db3");
  ASSERT_EQ(testing::WriteBagFile(mixed, {imu}), "");
  TriadLog both;
  ASSERT_TRUE(ReadImuLog(mixed, ImuLogReadOptions(), &both, ImuLogSpacing::kEven, &source).ok());
  EXPECT_TRUE(both.has_gyroscope());
}

TEST(Ros2Bag, AFolderAndItsDb3FileReadAsTheMessagesInMetresPerSecondSquaredAndRadiansPerSecond) {
  ScratchDir scratch;
  const TriadLog written = ExampleLog(300);
  BagTopic imu{"/imu/data"};
  imu.messages = testing::ImuMessages(written, 1700000000);
  BagTopic other{"/rosout", "rcl_interfaces/msg/Log"};
  other.messages = {{1700000000000000000, "x"}};
  const std::string folder = scratch.File("bag");
  ASSERT_EQ(mkdir(folder.c_str(), 0755), 0);
  ASSERT_EQ(testing::WriteBagFile(folder + "/bag_0.db3", {imu, other}), "");
  scratch.Write("bag/metadata.yaml", testing::BagMetadataYaml({"bag_0.db3"}));
  for (const std::string& path : {folder, folder + "/bag_0.db3"}) {
    TriadLog log;
    ImuLogSource source;
    ASSERT_TRUE(IsRos2Bag(path)) << path;
    const Status status =
        ReadImuLog(path, ImuLogReadOptions(), &log, ImuLogSpacing::kEven, &source);
    ASSERT_TRUE(status.ok()) << status.message();
    ASSERT_EQ(log.size(), written.size());
    for (size_t i = 0; i < log.size(); ++i) {
      EXPECT_EQ(log.timestamp_s[i],
                static_cast<double>(std::llround(written.timestamp_s[i] * 1e9)) * 1e-9);
      EXPECT_EQ(log.output[i], written.output[i]);
      EXPECT_EQ(log.gyroscope[i], written.gyroscope[i]);
    }
    EXPECT_EQ(source.accelerometer_unit, "m/s^2");
    EXPECT_EQ(source.gyroscope_unit, "rad/s");
    EXPECT_NE(source.layout.find("topic /imu/data"), std::string::npos) << source.layout;
    ASSERT_FALSE(source.notes.empty());
    EXPECT_NE(source.notes[0].find("the bag's one sensor_msgs/msg/Imu topic"), std::string::npos);
    EXPECT_NE(source.notes[1].find("time: the messages' header stamps"), std::string::npos);
  }
}

TEST(Ros2Bag, ASplitBagIsReadFileAfterFileAndAnOldSchemaToo) {
  ScratchDir scratch;
  const TriadLog written = ExampleLog(400);
  const std::vector<BagMessage> all = testing::ImuMessages(written, 1700000000);
  BagTopic first{"/imu"}, second{"/imu"};
  first.messages.assign(all.begin(), all.begin() + 150);
  second.messages.assign(all.begin() + 150, all.end());
  const std::string folder = scratch.File("split");
  ASSERT_EQ(mkdir(folder.c_str(), 0755), 0);
  ASSERT_EQ(testing::WriteBagFile(folder + "/split_0.db3", {first}, /*modern=*/false), "");
  ASSERT_EQ(testing::WriteBagFile(folder + "/split_1.db3", {second}), "");
  scratch.Write("split/metadata.yaml", testing::BagMetadataYaml({"split_0.db3", "split_1.db3"}));
  TriadLog log;
  ImuLogSource source;
  const Status status =
      ReadImuLog(folder, ImuLogReadOptions(), &log, ImuLogSpacing::kEven, &source);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(log.size(), 400u);
  EXPECT_EQ(log.output[399], written.output[399]);
  Ros2BagSource bag;
  ASSERT_TRUE(ReadRos2BagImuLog(folder, Ros2BagReadOptions(), &log, &bag).ok());
  EXPECT_EQ(bag.files, (std::vector<std::string>{folder + "/metadata.yaml", folder + "/split_0.db3",
                                                 folder + "/split_1.db3"}));
  // Without metadata.yaml: the .db3 files by their _N suffix (split_10 after split_1).
  ASSERT_EQ(unlink((folder + "/metadata.yaml").c_str()), 0);
  ASSERT_TRUE(ReadImuLog(folder, ImuLogReadOptions(), &log, ImuLogSpacing::kEven, &source).ok());
  EXPECT_EQ(log.size(), 400u);
}

Status ReadBag(const std::string& path, const std::string& topic, TriadLog* log,
               const std::string& bag_time = "header") {
  ImuLogReadOptions options;
  options.topic = topic;
  options.bag_time = bag_time;
  return ReadImuLog(path, options, log);
}

TEST(Ros2Bag, TheTopicIsChosenByTheFlagOrRefusedListingTheCandidates) {
  ScratchDir scratch;
  const TriadLog written = ExampleLog(300);
  BagTopic left{"/left/imu"}, right{"/right/imu"}, odometry{"/odom", "nav_msgs/msg/Odometry"};
  left.messages = testing::ImuMessages(written, 1700000000);
  right.messages = testing::ImuMessages(written, 1700000000, 3000000, "right");
  const std::string two = scratch.File("two.db3");
  ASSERT_EQ(testing::WriteBagFile(two, {left, right, odometry}), "");
  TriadLog log;
  EXPECT_ERROR_CONTAINS(ReadBag(two, "", &log),
                        "2 sensor_msgs/msg/Imu topics (/left/imu, /right/imu): name one with "
                        "--topic=/left/imu");
  EXPECT_TRUE(ReadBag(two, "/right/imu", &log).ok());
  EXPECT_ERROR_CONTAINS(ReadBag(two, "/odom", &log),
                        "--topic=/odom is of type nav_msgs/msg/Odometry, not sensor_msgs/msg/Imu; "
                        "its Imu topics: /left/imu, /right/imu");
  EXPECT_ERROR_CONTAINS(ReadBag(two, "/imu", &log),
                        "--topic=/imu is not in the bag; its topics: "
                        "/left/imu (sensor_msgs/msg/Imu)");
  const std::string none = scratch.File("none.db3");
  ASSERT_EQ(testing::WriteBagFile(none, {odometry}), "");
  EXPECT_ERROR_CONTAINS(ReadBag(none, "", &log),
                        "no sensor_msgs/msg/Imu topic in the bag; its topics: /odom "
                        "(nav_msgs/msg/Odometry)");
  EXPECT_ERROR_CONTAINS(ReadBag(scratch.Write("log.csv", "t,ax,ay,az\n0,1,2,3\n"), "/imu", &log),
                        "--topic and --bag_time are for ROS 2 bags");
}

TEST(Ros2Bag, TimeIsTheHeaderStampByDefaultOrTheReceiveTimeAndMustIncrease) {
  ScratchDir scratch;
  TriadLog written = ExampleLog(300);
  BagTopic imu{"/imu"};
  imu.messages = testing::ImuMessages(written, 1700000000);
  // Receive times with a latency that grows: 2 ms, then 2.5 ms from message 100 on.
  for (size_t i = 100; i < imu.messages.size(); ++i) imu.messages[i].receive_ns += 500000;
  const std::string bag = scratch.File("bag.db3");
  ASSERT_EQ(testing::WriteBagFile(bag, {imu}), "");
  TriadLog log;
  ASSERT_TRUE(ReadBag(bag, "", &log).ok());
  EXPECT_NEAR(log.timestamp_s[150] - log.timestamp_s[50], 1.0, 1e-12);
  ImuLogReadOptions options;
  options.bag_time = "receive";
  ASSERT_TRUE(ReadImuLog(bag, options, &log, ImuLogSpacing::kAny).ok());
  EXPECT_NEAR(log.timestamp_s[150] - log.timestamp_s[50], 1.0005, 1e-12);
  // Two messages with one stamp (a driver that stamps a burst once).
  BagTopic repeated{"/imu"};
  written.timestamp_s[200] = written.timestamp_s[199];
  repeated.messages = testing::ImuMessages(written, 1700000000);
  repeated.messages[200].receive_ns += 1000;
  const std::string stale = scratch.File("stale.db3");
  ASSERT_EQ(testing::WriteBagFile(stale, {repeated}), "");
  EXPECT_ERROR_CONTAINS(ReadBag(stale, "", &log),
                        "its header stamp 1700000001.990000000 s does not increase from the "
                        "previous message's 1700000001.990000000 s");
  EXPECT_TRUE(ReadImuLog(stale, options, &log, ImuLogSpacing::kAny).ok());
}

TEST(Ros2Bag, DamagedBagsAreRefusedInOneLineNamingTheFile) {
  ScratchDir scratch;
  BagTopic imu{"/imu"};
  imu.messages = testing::ImuMessages(ExampleLog(2000), 1700000000);
  const std::string good = scratch.File("good.db3");
  ASSERT_EQ(testing::WriteBagFile(good, {imu}), "");
  const std::string bytes = testing::ReadText(good);
  TriadLog log;
  // Cut short: half the file.
  const std::string cut = scratch.Write("cut.db3", bytes.substr(0, bytes.size() / 2));
  EXPECT_ERROR_CONTAINS(ReadBag(cut, "", &log), cut + ": the file is cut short");
  // The SQLite header and then nothing of a database.
  const std::string header_only =
      scratch.Write("header.db3", std::string(kSqliteHeader, 16) + std::string(200, 'x'));
  const Status garbage = ReadBag(header_only, "", &log);
  EXPECT_FALSE(garbage.ok());
  EXPECT_EQ(garbage.message().rfind(header_only + ": ", 0), 0u) << garbage.message();
  // An SQLite database of something else.
  const std::string other = scratch.File("other.db3");
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(other.c_str(), &db), SQLITE_OK);
    std::string error;
    ASSERT_TRUE(testing::ExecuteSql(db, "CREATE TABLE readings(t REAL, x REAL);", &error));
    sqlite3_close(db);
  }
  EXPECT_ERROR_CONTAINS(ReadBag(other, "", &log),
                        other + ": an SQLite database without the table 'topics'");
  // A message cut short, and a topic that says Imu but holds another type.
  BagTopic short_message = imu;
  short_message.messages[700].data.resize(100);
  const std::string shortened = scratch.File("short.db3");
  ASSERT_EQ(testing::WriteBagFile(shortened, {short_message}), "");
  EXPECT_ERROR_CONTAINS(ReadBag(shortened, "", &log),
                        shortened +
                            ": message id 701 (topic /imu): the message is cut short: "
                            "orientation_covariance needs 8 bytes from byte 100, the "
                            "message has 100");
  BagTopic strings{"/imu"};
  strings.messages = {{1, std::string("\0\x01\0\0\x06\0\0\0hello\0\0\0", 16)}};
  const std::string wrong = scratch.File("wrong.db3");
  ASSERT_EQ(testing::WriteBagFile(wrong, {strings}), "");
  EXPECT_ERROR_CONTAINS(ReadBag(wrong, "", &log), wrong + ": message id 1 (topic /imu): ");
  // MCAP and a compressed bag: the conversion to say.
  const std::string mcap = scratch.Write("bag.mcap", std::string("\x89MCAP0\r\n", 8) + "rest");
  EXPECT_ERROR_CONTAINS(ReadBag(mcap, "", &log), "ros2 bag convert");
  const std::string folder = scratch.File("zstd");
  ASSERT_EQ(mkdir(folder.c_str(), 0755), 0);
  scratch.Write("zstd/metadata.yaml", testing::BagMetadataYaml({"zstd_0.db3.zstd"}));
  EXPECT_ERROR_CONTAINS(ReadBag(folder, "", &log), "ros2 bag decompress");
  scratch.Write("zstd/metadata.yaml", testing::BagMetadataYaml({"zstd_0.mcap"}, "mcap"));
  EXPECT_ERROR_CONTAINS(ReadBag(folder, "", &log), "MCAP storage is not read here");
  // A file the metadata lists that is not there.
  scratch.Write("zstd/metadata.yaml", testing::BagMetadataYaml({"zstd_0.db3"}));
  EXPECT_ERROR_CONTAINS(ReadBag(folder, "", &log), "it lists 'zstd_0.db3', which is not a file");
  // Text-log flags are refused rather than ignored.
  ImuLogReadOptions options;
  options.rate_hz = 100.0;
  EXPECT_ERROR_CONTAINS(ReadImuLog(good, options, &log), "--rate_hz is for text and .mat logs");
}

// The run's record of the bytes read (the provenance's checksums) covers every .db3 file.
TEST(Ros2Bag, TheRunRecordsEveryFileOfTheBagItRead) {
  ScratchDir scratch;
  BagTopic imu{"/imu"};
  imu.messages = testing::ImuMessages(ExampleLog(300), 1700000000);
  const std::string folder = scratch.File("bag");
  ASSERT_EQ(mkdir(folder.c_str(), 0755), 0);
  ASSERT_EQ(testing::WriteBagFile(folder + "/bag_0.db3", {imu}), "");
  scratch.Write("bag/metadata.yaml", testing::BagMetadataYaml({"bag_0.db3"}));
  StartRecordingInputReads();
  TriadLog log;
  ASSERT_TRUE(ReadImuLog(folder, &log).ok());
  InputRead read;
  EXPECT_TRUE(FindInputRead(folder + "/bag_0.db3", &read));
  EXPECT_EQ(read.bytes, testing::ReadText(folder + "/bag_0.db3").size());
  EXPECT_TRUE(FindInputRead(folder + "/metadata.yaml", &read));
  // The folder stands for its files in the provenance.
  std::vector<InputFolderPart> parts;
  ASSERT_TRUE(FindInputFolder(folder, &parts));
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].role_suffix, "");
  EXPECT_EQ(parts[0].path, folder + "/bag_0.db3");
  EXPECT_EQ(parts[1].role_suffix, "_metadata");
}

}  // namespace
}  // namespace accelcal
