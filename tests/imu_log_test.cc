// The IMU log readers (io/imu_log.h, io/imu_log_format.h): every layout of
// docs/log-layouts.md, streamed and whole, and their refusals.

#include "io/imu_log.h"

#include <gtest/gtest.h>
#include <matio.h>

#include <cstdint>
#include <functional>
#include <string>

#include "common/format.h"
#include "io/mat_file.h"
#include "test_support.h"

namespace accelcal {
namespace {

std::string Refusal(const std::string& text, const ImuLogReadOptions& options = {}) {
  TriadLog log;
  const Status status = ParseImuLog(text, options, &log);
  EXPECT_FALSE(status.ok()) << text;
  return status.message();
}

const ImuLogReadOptions kAscii;  // the layout is told from the text
const ImuLogReadOptions kCsv;

TEST(ImuLog, ReadsImuTksAsciiLayout) {
  TriadLog log;
  const Status status = ParseImuLog(
      "   2.9840000e-02   3.3108000e+04   3.3329000e+04   3.6429000e+04\n"
      "# a comment\n\n"
      "\t3.9857000e-02\t33096 33336   36437\r\n",
      kAscii, &log);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(log.size(), 2u);
  EXPECT_DOUBLE_EQ(log.timestamp_s[1], 0.039857);
  EXPECT_DOUBLE_EQ(log.output[1][2], 36437.0);
}

TEST(ImuLog, ReadsTheCsvLayout) {
  TriadLog log;
  const Status status =
      ParseImuLog("t_s,acc_x,acc_y,acc_z\n0.00,0.1,0.2,9.8\n0.01,0.1,0.2,9.79\n", kCsv, &log);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(log.size(), 2u);
  EXPECT_DOUBLE_EQ(log.output[1][2], 9.79);
}

TEST(ImuLog, RefusesAWrongColumnCountWithTheLine) {
  const std::string message =
      Refusal("0.00 1 2 3\n0.01 1 2 3\n0.02 1 2 3\n0.03 1 2 3\n0.04 1 2 3\n0.05 1 2\n");
  EXPECT_NE(message.find("line 6: 3 field(s), expected 4 (as line 1)"), std::string::npos)
      << message;
  const std::string csv = Refusal(
      "t_s,acc_x,acc_y,acc_z\n0.00,1,2,3\n0.01,1,2,3\n0.02,1,2,3\n0.03,1,2,3\n0.04,1,2,3\n"
      "0.05,1,2\n");
  EXPECT_NE(csv.find("line 7: 3 field(s), expected 4 (as the header on line 1)"), std::string::npos)
      << csv;
}

TEST(ImuLog, RefusesValuesThatAreNotFinite) {
  const std::string message = Refusal("0.00 1 2 3\n0.01 1 nan 3\n", kAscii);
  EXPECT_NE(message.find("line 2, column 3 (ay): 'nan' is not a finite number"), std::string::npos)
      << message;
  const std::string text = Refusal("0.00 1 2 3\n0.01 1 abc 3\n", kAscii);
  EXPECT_NE(text.find("'abc' is not a number"), std::string::npos) << text;
  const std::string csv = Refusal("t_s,acc_x,acc_y,acc_z\n0,1,2,3\n0.01,1,2,inf\n", kCsv);
  EXPECT_NE(csv.find("column 'acc_z' (az): 'inf' is not a finite number"), std::string::npos)
      << csv;
}

TEST(ImuLog, RefusesTimeThatDoesNotIncrease) {
  const std::string message = Refusal("0.00 1 2 3\n0.01 1 2 3\n0.01 1 2 3\n", kAscii);
  EXPECT_NE(message.find("line 3: time 0.01 s does not increase"), std::string::npos) << message;
}

TEST(ImuLog, RefusesATimeAxisInMillisecondsWhenTheNameSaysSeconds) {
  const std::string message = Refusal("t_s,ax,ay,az\n0,1,2,3\n10,1,2,3\n20,1,2,3\n");
  EXPECT_NE(message.find("time 't_s' steps by 10 s as read, 0.1 Hz, outside an IMU log's 1 Hz to "
                         "100 kHz; read in ms it steps by 0.01 s (100 Hz): give --time_unit=ms"),
            std::string::npos)
      << message;
}

// 100 samples 0.01 s apart from t = 0, then 100 more `step_s` apart, from `second_start_s`.
std::string TwoPartLog(double second_start_s, double step_s) {
  std::string text;
  for (int j = 0; j < 200; ++j) {
    const double t_s = j < 100 ? 0.01 * j : second_start_s + step_s * (j - 100);
    text += StringPrintf("%.6f 33000 33100 36400\n", t_s);
  }
  return text;
}

TEST(ImuLog, RefusesAGapOrARateChangeForCalibrationButNotForCorrection) {
  const std::string joined = TwoPartLog(30.0, 0.01);
  std::string message = Refusal(joined, kAscii);
  EXPECT_NE(message.find("sample 101 (t = 30 s)"), std::string::npos) << message;
  EXPECT_NE(message.find("the log has a gap"), std::string::npos) << message;
  message = Refusal(TwoPartLog(1.0, 0.05), kAscii);
  EXPECT_NE(message.find("the sampling rate changes within the log"), std::string::npos) << message;
  TriadLog log;
  EXPECT_TRUE(ParseImuLog(joined, kAscii, &log, ImuLogSpacing::kAny).ok());
  EXPECT_EQ(log.size(), 200u);
  // Real jitter passes: steps from 0.96 to 1.04 of the median, as in imu_tk's Xsens log.
  std::string jitter;
  for (int j = 0; j < 200; ++j)
    jitter += StringPrintf("%.6f 33000 33100 36400\n", 0.01 * j + (j % 3 == 1 ? 0.0004 : 0.0));
  const Status status = ParseImuLog(jitter, kAscii, &log);
  EXPECT_TRUE(status.ok()) << status.message();
  // Host time stamps that bunch (a step of 0.2 then 1.8 medians) and a few lost samples (steps
  // of 2 to 9 medians) pass: a pose's mean and variance are those of the samples it holds.
  std::string bunched;
  double t_s = 0.0;
  for (int j = 0; j < 1000; ++j) {
    bunched += StringPrintf("%.6f 33000 33100 36400\n", t_s);
    t_s += j % 7 == 3 ? 0.002 : j % 7 == 4 ? 0.018 : j == 500 ? 0.09 : j % 97 == 0 ? 0.02 : 0.01;
  }
  const Status bunched_status = ParseImuLog(bunched, kAscii, &log);
  EXPECT_TRUE(bunched_status.ok()) << bunched_status.message();
  // Ten lost samples are not: 11 median steps.
  message = Refusal(TwoPartLog(1.10, 0.01), kAscii);
  EXPECT_NE(message.find("the log has a gap"), std::string::npos) << message;
}

TEST(ImuLog, RefusesAFileCutShort) {
  const std::string message = Refusal("0.00 1 2 3\n0.01 1 2", kAscii);
  EXPECT_NE(message.find("line 2 has no line end"), std::string::npos) << message;
}

TEST(ImuLog, RefusesAnEmptyLog) {
  const std::string message = Refusal("# nothing\n", kAscii);
  EXPECT_NE(message.find("no samples"), std::string::npos) << message;
}

TEST(ImuLog, NamesTheFileWhenReadingFromDisk) {
  testing::ScratchDir dir;
  const std::string path = dir.Write("bad.txt", "0.00 1 2 3\n0.01 1 2 x\n");
  TriadLog log;
  const Status status = ReadImuLog(path, &log);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.message().rfind(path + ": line 2, column 4 (az)", 0), 0u) << status.message();
  const Status missing = ReadImuLog(dir.File("absent.mat"), &log);
  EXPECT_FALSE(missing.ok());
}

TEST(ImuLog, StreamsInBatchesWhatIsReadWhole) {
  testing::ScratchDir dir;
  std::string text;
  for (int i = 0; i < 1000; ++i)
    text += StringPrintf("%.2f %d %d %d\n", 0.01 * (i + 1), i, 2 * i, 3 * i);
  const std::string path = dir.Write("log.mat", text);
  TriadLog whole;
  ASSERT_TRUE(ReadImuLog(path, &whole).ok());
  size_t streamed = 0;
  int batches = 0;
  const Status status = StreamImuLog(path, ImuLogReadOptions(), 64, [&](const TriadLog& batch) {
    EXPECT_LE(batch.size(), 64u);
    for (size_t j = 0; j < batch.size(); ++j) {
      EXPECT_EQ(batch.output[j], whole.output[streamed + j]);
    }
    streamed += batch.size();
    ++batches;
  });
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(streamed, 1000u);
  EXPECT_EQ(batches, 16);
}

// --- The layouts users record (docs/log-layouts.md), one test each. ---

// `rows` rows of a 100 Hz still sensor: t, then the accelerometer (1, 2, 9.8) and gyroscope
// (0.01, 0.02, 0.03), written by `row`.
std::string Rows(int rows, const std::function<std::string(int j, double t_s)>& row) {
  std::string text;
  for (int j = 0; j < rows; ++j) text += row(j, 0.01 * j);
  return text;
}

TriadLog ReadOk(const std::string& text, const ImuLogReadOptions& options = {},
                ImuLogSource* source = nullptr) {
  TriadLog log;
  const Status status = ParseImuLog(text, options, &log, ImuLogSpacing::kEven, source);
  EXPECT_TRUE(status.ok()) << status.message() << "\n" << text.substr(0, 400);
  return log;
}

void ExpectStillSensor(const TriadLog& log, int rows, double step_s, bool gyroscope) {
  ASSERT_EQ(log.size(), static_cast<size_t>(rows));
  EXPECT_NEAR(log.timestamp_s[1] - log.timestamp_s[0], step_s, 1e-9);
  EXPECT_DOUBLE_EQ(log.output[rows - 1][0], 1.0);
  EXPECT_DOUBLE_EQ(log.output[rows - 1][2], 9.8);
  EXPECT_EQ(log.has_gyroscope(), gyroscope);
  if (gyroscope) EXPECT_DOUBLE_EQ(log.gyroscope[rows - 1][2], 0.03);
}

bool HasNote(const ImuLogSource& source, const std::string& fragment) {
  for (const std::string& note : source.notes) {
    if (note.find(fragment) != std::string::npos) return true;
  }
  return false;
}

TEST(ImuLogLayouts, CsvWithGyroscopeColumnsAndShortNames) {
  ImuLogSource source;
  const TriadLog log = ReadOk(
      "t,ax,ay,az,gx,gy,gz\n" +
          Rows(50, [](int, double t) { return StringPrintf("%.2f,1,2,9.8,0.01,0.02,0.03\n", t); }),
      {}, &source);
  ExpectStillSensor(log, 50, 0.01, true);
  EXPECT_NE(source.layout.find("gyroscope 'gx', 'gy', 'gz'"), std::string::npos) << source.layout;
  EXPECT_TRUE(HasNote(source, "inferred from its median step 0.01 (100 Hz")) << source.layout;
}

TEST(ImuLogLayouts, ImucalNamesAndColumnOrder) {
  // imucal writes the gyroscope first, and acc_x...gyr_z names.
  const TriadLog log =
      ReadOk("time_s,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z\n" + Rows(30, [](int, double t) {
               return StringPrintf("%.2f,0.01,0.02,0.03,1,2,9.8\n", t);
             }));
  ExpectStillSensor(log, 30, 0.01, true);
}

TEST(ImuLogLayouts, SemicolonsDecimalCommasAndMetadataBeforeTheHeader) {
  ImuLogSource source;
  const TriadLog log =
      ReadOk("Device;MPU-6050\nFs;100\n\nTime [ms];ACCEL_X;ACCEL_Y;ACCEL_Z\n" +
                 Rows(40, [](int j, double) { return StringPrintf("%d;1,0;2,0;9,8\n", 10 * j); }),
             {}, &source);
  ExpectStillSensor(log, 40, 0.01, false);
  ASSERT_EQ(source.metadata.size(), 2u);
  EXPECT_EQ(source.metadata[0], "Device;MPU-6050");
  EXPECT_TRUE(HasNote(source, "decimal comma"));
  EXPECT_TRUE(HasNote(source, "in ms (its name says so)"));
}

TEST(ImuLogLayouts, TabsCamelCaseAndATimeInMicrosecondsInferred) {
  ImuLogSource source;
  const TriadLog log =
      ReadOk("timestamp\tAccX\tAccY\tAccZ\tGyroX\tGyroY\tGyroZ\n" +
                 Rows(60,
                      [](int j, double) {
                        return StringPrintf("%d\t1\t2\t9.8\t0.01\t0.02\t0.03\n", 2500 * j);
                      }),
             {}, &source);
  ExpectStillSensor(log, 60, 0.0025, true);
  EXPECT_TRUE(HasNote(source, "in us, inferred from its median step 2500 (400 Hz"))
      << source.layout;
}

TEST(ImuLogLayouts, EurocHeaderInACommentNanosecondEpochAndStatedUnits) {
  ImuLogSource source;
  const TriadLog log = ReadOk(
      "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
      "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n" +
          Rows(40,
               [](int j, double) {
                 return StringPrintf("%lld,0.01,0.02,0.03,1,2,9.8\n",
                                     1403636579758555392LL + 5000000LL * j);
               }),
      {}, &source);
  ExpectStillSensor(log, 40, 0.005, true);
  EXPECT_DOUBLE_EQ(log.timestamp_s[0], 0.0);
  EXPECT_DOUBLE_EQ(log.timestamp_s[39], 0.195);  // exact: integer nanoseconds counted as such
  EXPECT_EQ(source.accelerometer_unit, "m/s^2");
  EXPECT_EQ(source.gyroscope_unit, "rad/s");
  EXPECT_TRUE(HasNote(source, "times here are from the first sample"));
}

TEST(ImuLogLayouts, UnixMillisecondsWithBleJitterAreInferredBySize) {
  ImuLogSource source;
  // Host stamps of a 50 Hz BLE stream: bunched by the radio's connection interval.
  const TriadLog log =
      ReadOk("time,x_acc,y_acc,z_acc\n" + Rows(200,
                                               [](int j, double) {
                                                 const long long t = 1732650000000LL + 20 * j +
                                                                     (j % 3 == 1 ? 3 : 0);
                                                 return StringPrintf("%lld,1,2,9.8\n", t);
                                               }),
             {}, &source);
  ASSERT_EQ(log.size(), 200u);
  EXPECT_NEAR(log.timestamp_s[198], 3.96, 1e-12);
  EXPECT_NEAR(log.timestamp_s[199], 3.983, 1e-12);
  EXPECT_TRUE(HasNote(source, "a Unix time in ms by its size")) << source.notes.size();
}

TEST(ImuLogLayouts, NoTimeColumnTakesTheRateOrASampleNumber) {
  const std::string rows = "ax,ay,az\n" + Rows(30, [](int, double) { return "1,2,9.8\n"; });
  const std::string message = Refusal(rows);
  EXPECT_NE(message.find("give --rate_hz=R"), std::string::npos) << message;
  ImuLogReadOptions options;
  options.rate_hz = 50.0;
  ExpectStillSensor(ReadOk(rows, options), 30, 0.02, false);
  // imucal's annotated session: a text label, a sample number, raw counts.
  const std::string imucal =
      "part,samples,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n" + Rows(30, [](int j, double) {
        return StringPrintf("x_p,%d,1,2,9.8,0.01,0.02,0.03\n", 100 + 2 * j);
      });
  const std::string index_message = Refusal(imucal);
  EXPECT_NE(index_message.find("'samples' numbers the samples: give --rate_hz"), std::string::npos)
      << index_message;
  ExpectStillSensor(ReadOk(imucal, options), 30, 0.04, true);
}

TEST(ImuLogLayouts, ASampleNumberIsNotTakenForATime) {
  const std::string message = Refusal(
      "t,ax,ay,az\n" + Rows(30, [](int j, double) { return StringPrintf("%d,1,2,9.8\n", j); }));
  EXPECT_NE(message.find("a sample number, not a time; give --rate_hz=R"), std::string::npos)
      << message;
}

// Issue 35, item 4: a 100 Hz log whose time column is the sample index (0, 1, 2, ... N-1) is
// never read as 1 Hz without a word, whatever its name says: refused naming --rate_hz and
// --time_unit, a sample dropped or not; --rate_hz gives its time, and --time_unit=s, which says
// it is a 1 Hz log, reads it so and says so.
TEST(ImuLogLayouts, ASampleIndexAsTimeIsRefusedWhateverTheColumnsNameSays) {
  const int rows = 3000;  // 30 s at 100 Hz
  auto log_with = [rows](const std::string& header, int dropped) {
    std::string text = header.empty() ? "" : header + ",ax,ay,az\n";
    const char separator = header.empty() ? ' ' : ',';
    for (int j = 0; j < rows; ++j) {
      if (j == dropped) continue;
      text += StringPrintf("%d%c1%c2%c9.8\n", j, separator, separator, separator);
    }
    return text;
  };
  for (const std::string header : {"t", "t_s", "time [s]", "Time (s)", "timestamp_s", ""}) {
    for (const int dropped : {-1, 1500}) {
      SCOPED_TRACE("header '" + header + "', dropped " + std::to_string(dropped));
      const std::string message = Refusal(log_with(header, dropped));
      EXPECT_NE(message.find("counts 0, 1, 2, ... by 1"), std::string::npos) << message;
      EXPECT_NE(message.find("--rate_hz=R"), std::string::npos) << message;
      EXPECT_NE(message.find("--time_unit=s"), std::string::npos) << message;
    }
  }
  ImuLogReadOptions rate;
  rate.rate_hz = 100.0;
  EXPECT_NEAR(ReadOk(log_with("t_s", -1), rate).timestamp_s[1], 0.01, 1e-12);
  ImuLogReadOptions seconds;
  seconds.time_unit = "s";
  ImuLogSource source;
  const TriadLog one_hz = ReadOk(log_with("t_s", -1), seconds, &source);
  EXPECT_DOUBLE_EQ(one_hz.timestamp_s[1], 1.0);
  ASSERT_FALSE(source.notes.empty());
  EXPECT_NE(source.notes[0].find("in s (--time_unit)"), std::string::npos) << source.notes[0];
  // A time in ms that counts by 1 is a 1 kHz log its name states: read so.
  EXPECT_NEAR(ReadOk(log_with("t_ms", -1)).timestamp_s[1], 0.001, 1e-12);
}

// The suggestion a refusal prints (from "--columns=" to the end of its word), followed.
std::string SuggestedColumns(const std::string& message) {
  const size_t start = message.find("--columns=");
  EXPECT_NE(start, std::string::npos) << message;
  if (start == std::string::npos) return "";
  const size_t end = message.find_first_of(" )", start);
  return message.substr(start + 10,
                        end == std::string::npos ? std::string::npos : end - start - 10);
}

TEST(ImuLogLayouts, SeveralAccelerometersAreRefusedAndTheSuggestionWorks) {
  const std::string text =
      "TIME,ACCEL_BMI160_0_X,ACCEL_BMI160_0_Y,ACCEL_BMI160_0_Z,ACCEL_BMI160_1_X,ACCEL_BMI160_1_Y,"
      "ACCEL_BMI160_1_Z\n" +
      Rows(30, [](int, double t) { return StringPrintf("%.2f,1,2,9.8,5,6,7\n", t); });
  const std::string message = Refusal(text);
  EXPECT_NE(message.find("2 accelerometers"), std::string::npos) << message;
  EXPECT_NE(message.find("'ACCEL_BMI160_1_X'"), std::string::npos) << message;
  ImuLogReadOptions options;
  options.columns = SuggestedColumns(message);
  ExpectStillSensor(ReadOk(text, options), 30, 0.01, false);
  options.columns = "ax:ACCEL_BMI160_1_X,ay:ACCEL_BMI160_1_Y,az:5";  // a name, or a number from 1
  // ACCEL_BMI160_1_Z is column 7; column 5 is ACCEL_BMI160_1_X, which two roles cannot share.
  EXPECT_NE(Refusal(text, options).find("two roles"), std::string::npos);
  options.columns = "ax:ACCEL_BMI160_1_X,ay:ACCEL_BMI160_1_Y,az:7";
  const TriadLog second = ReadOk(text, options);
  ASSERT_EQ(second.size(), 30u);
  EXPECT_DOUBLE_EQ(second.output[0][2], 7.0);
}

TEST(ImuLogLayouts, HeaderlessRowsOfSevenNeedNamesAndTheSuggestionWorks) {
  const std::string text =
      Rows(30, [](int, double t) { return StringPrintf("%.2f 1 2 9.8 0.01 0.02 0.03\n", t); });
  const std::string message = Refusal(text);
  EXPECT_NE(message.find("7 numbers per row and no header"), std::string::npos) << message;
  ImuLogReadOptions options;
  options.columns = SuggestedColumns(message);
  ExpectStillSensor(ReadOk(text, options), 30, 0.01, false);
  options.columns += ",gx:5,gy:6,gz:7";
  ExpectStillSensor(ReadOk(text, options), 30, 0.01, true);
}

TEST(ImuLogLayouts, RostopicCsvWithTwoTimeColumnsSaysWhichItUses) {
  ImuLogSource source;
  const TriadLog log = ReadOk(
      "%time,field.header.seq,field.header.stamp,field.angular_velocity.x,"
      "field.angular_velocity.y,field.angular_velocity.z,field.linear_acceleration.x,"
      "field.linear_acceleration.y,field.linear_acceleration.z\n" +
          Rows(30,
               [](int j, double) {
                 const long long t = 1600000000000000000LL + 10000000LL * j;
                 return StringPrintf("%lld,%d,%lld,0.01,0.02,0.03,1,2,9.8\n", t + 1000, j, t);
               }),
      {}, &source);
  ExpectStillSensor(log, 30, 0.01, true);
  EXPECT_TRUE(HasNote(source, "not 'field.header.stamp'")) << source.notes.size();
}

TEST(ImuLogLayouts, RefusesWhatIsNotAUtf8TextLogSayingWhy) {
  EXPECT_NE(Refusal(std::string("\xFF\xFEt\0,\0", 6)).find("UTF-16"), std::string::npos);
  EXPECT_NE(Refusal("t,ax,ay,az\r0,1,2,3\r").find("carriage return alone"), std::string::npos);
  const std::string none = Refusal("t,ax,ay,az\nmag_x,mag_y\n");
  EXPECT_NE(none.find("no rows of numbers"), std::string::npos) << none;
  const std::string mag = Refusal("t,mag_x,mag_y,mag_z\n" + Rows(10, [](int, double t) {
                                    return StringPrintf("%.2f,1,2,3\n", t);
                                  }));
  EXPECT_NE(mag.find("no accelerometer columns in the header"), std::string::npos) << mag;
}

TEST(ImuLogLayouts, ClassifiesTheAliasTable) {
  struct Case {
    const char* name;
    ImuColumnKind kind;
    int axis;
  };
  const Case cases[] = {{"t", ImuColumnKind::kTime, -1},
                        {"Time (s)", ImuColumnKind::kTime, -1},
                        {"timestamp_us", ImuColumnKind::kTime, -1},
                        {"%time", ImuColumnKind::kTime, -1},
                        {"n_samples", ImuColumnKind::kSampleIndex, -1},
                        {"ax", ImuColumnKind::kAccelerometer, 0},
                        {"acc_y", ImuColumnKind::kAccelerometer, 1},
                        {"ACCEL_Z", ImuColumnKind::kAccelerometer, 2},
                        {"accelerometer.x", ImuColumnKind::kAccelerometer, 0},
                        {"AccY", ImuColumnKind::kAccelerometer, 1},
                        {"acc_z_g", ImuColumnKind::kAccelerometer, 2},
                        {"alpha_x", ImuColumnKind::kAccelerometer, 0},  // Kalibr's
                        {"millis", ImuColumnKind::kTime, -1},           // Arduino's
                        {"Zeit [ms]", ImuColumnKind::kTime, -1},
                        {"SampleTimeFine", ImuColumnKind::kTime, -1},  // Xsens's
                        {"PacketCounter", ImuColumnKind::kSampleIndex, -1},
                        {"gx", ImuColumnKind::kGyroscope, 0},
                        {"gyr_y", ImuColumnKind::kGyroscope, 1},
                        {"gyro_z_dps", ImuColumnKind::kGyroscope, 2},
                        {"angular_velocity.x", ImuColumnKind::kGyroscope, 0},
                        {"mag_x", ImuColumnKind::kOther, -1},
                        {"gravity_x", ImuColumnKind::kOther, -1},
                        {"temperature", ImuColumnKind::kOther, -1}};
  for (const Case& c : cases) {
    const ImuColumnName name = ClassifyImuColumnName(c.name);
    EXPECT_EQ(name.kind, c.kind) << c.name;
    EXPECT_EQ(name.axis, c.axis) << c.name;
  }
  EXPECT_EQ(ClassifyImuColumnName("timestamp_us").time_unit, "us");
  EXPECT_EQ(ClassifyImuColumnName("acc_z_g").value_unit, "g");
  EXPECT_EQ(ClassifyImuColumnName("millis").time_unit, "ms");
  EXPECT_EQ(ClassifyImuColumnName("a_x [m/s\xc2\xb2]").value_unit, "m/s^2");
  EXPECT_EQ(ClassifyImuColumnName("ACCEL_BMI160_1_X").device, "bmi160_1");
}

TEST(ImuLogLayouts, ImuTksPairOfFilesAndAMatFileWithNamedVariables) {
  testing::ScratchDir dir;
  const std::string accelerometer = dir.Write(
      "acc.mat", Rows(30, [](int, double t) { return StringPrintf("%.2f 1 2 9.8\n", t + 0.03); }));
  const std::string gyroscope = dir.Write("gyro.mat", Rows(30, [](int, double t) {
                                            return StringPrintf("%.2f 0.01 0.02 0.03\n", t + 0.03);
                                          }));
  ImuLogReadOptions options;
  options.gyroscope_path = gyroscope;
  TriadLog log;
  Status status = ReadImuLog(accelerometer, options, &log);
  ASSERT_TRUE(status.ok()) << status.message();
  ExpectStillSensor(log, 30, 0.01, true);
  // Time stamps that differ are refused, naming the sample.
  const std::string shifted = dir.Write("shifted.mat", Rows(30, [](int, double t) {
                                          return StringPrintf("%.2f 0.01 0.02 0.03\n", t + 0.04);
                                        }));
  options.gyroscope_path = shifted;
  status = ReadImuLog(accelerometer, options, &log);
  EXPECT_NE(status.message().find("sample 1 is at t = 0.04 s, the accelerometer's at 0.03 s"),
            std::string::npos)
      << status.message();

  // A binary MATLAB v5 file: a time vector and N x 3 accelerometer and gyroscope matrices.
  MatMatrix t{30, 1, {}}, acc{30, 3, {}}, gyr{3, 30, {}};  // the gyroscope stored 3 x N
  for (int j = 0; j < 30; ++j) t.values.push_back(0.01 * j);
  for (double value : {1.0, 2.0, 9.8}) acc.values.insert(acc.values.end(), 30, value);
  for (int j = 0; j < 30; ++j) gyr.values.insert(gyr.values.end(), {0.01, 0.02, 0.03});
  const std::string mat = dir.File("session.mat");
  ASSERT_TRUE(WriteMatFile(mat, {{"t", t}, {"acc", acc}, {"gyr", gyr}}).ok());
  ImuLogSource source;
  status = ReadImuLog(mat, ImuLogReadOptions(), &log, ImuLogSpacing::kEven, &source);
  ASSERT_TRUE(status.ok()) << status.message();
  ExpectStillSensor(log, 30, 0.01, true);
  EXPECT_NE(source.layout.find("accelerometer acc(:,1), acc(:,2), acc(:,3)"), std::string::npos)
      << source.layout;
  // Version 7.3 (HDF5), as MATLAB's -v7.3 writes it: separate vectors per axis.
  const std::string mat73 = dir.File("session73.mat");
  mat_t* file = Mat_CreateVer(mat73.c_str(), nullptr, MAT_FT_MAT73);
  ASSERT_NE(file, nullptr) << "libmatio was built without HDF5";
  std::vector<double> ax(30, 1.0), ay(30, 2.0), az(30, 9.8);
  size_t dims[2] = {30, 1};
  for (auto [name, values] :
       {std::make_pair("time", t.values.data()), std::make_pair("ax", ax.data()),
        std::make_pair("ay", ay.data()), std::make_pair("az", az.data())}) {
    matvar_t* var =
        Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, values, MAT_F_DONT_COPY_DATA);
    ASSERT_EQ(Mat_VarWrite(file, var, MAT_COMPRESSION_NONE), 0);
    Mat_VarFree(var);
  }
  Mat_Close(file);
  status = ReadImuLog(mat73, ImuLogReadOptions(), &log, ImuLogSpacing::kEven, &source);
  ASSERT_TRUE(status.ok()) << status.message();
  ExpectStillSensor(log, 30, 0.01, false);
  EXPECT_NE(source.layout.find("t = time; accelerometer ax, ay, az"), std::string::npos)
      << source.layout;
  // The course's two-axis file is told apart from a triad log.
  const std::string two_axis = dir.File("ensayo.mat");
  ASSERT_TRUE(WriteMatFile(two_axis,
                           {{"tita", t}, {"datos", MatMatrix{30, 2, std::vector<double>(60, 1.0)}}})
                  .ok());
  status = ReadImuLog(two_axis, &log);
  EXPECT_NE(
      status.message().find("no accelerometer among the variables (tita (30x1), datos (30x2))"),
      std::string::npos)
      << status.message();
  options = ImuLogReadOptions();
  options.columns = "t:tita,ax:datos(:,1),ay:datos(:,2),az:datos(:,2)";
  EXPECT_TRUE(ReadImuLog(two_axis, options, &log).ok());
}

// --- What the outside probe of 2026-11-26 found (each failed before its fix). ---

TEST(ImuLogProbe, APairOfFilesWithHeadersIsRead) {
  testing::ScratchDir dir;
  const std::string accelerometer = dir.Write(
      "acc.csv",
      "t,ax,ay,az\n" + Rows(30, [](int, double t) { return StringPrintf("%.2f,1,2,9.8\n", t); }));
  // The gyroscope's file names its columns (the probe's crash: exit 139), or, as a phone app's,
  // has bare x, y, z (z first).
  for (const std::string& header : {"t,gx,gy,gz", "t,z,y,x"}) {
    const bool bare = header[2] == 'z';
    const std::string gyroscope =
        dir.Write("gyro.csv", header + "\n" + Rows(30, [bare](int, double t) {
                                return StringPrintf(
                                    bare ? "%.2f,0.03,0.02,0.01\n" : "%.2f,0.01,0.02,0.03\n", t);
                              }));
    ImuLogReadOptions options;
    options.gyroscope_path = gyroscope;
    TriadLog log;
    ImuLogSource source;
    const Status status = ReadImuLog(accelerometer, options, &log, ImuLogSpacing::kEven, &source);
    ASSERT_TRUE(status.ok()) << status.message();
    ExpectStillSensor(log, 30, 0.01, true);
    EXPECT_TRUE(HasNote(source, bare ? "gyroscope 'x', 'y', 'z')" : "gyroscope 'gx', 'gy', 'gz')"))
        << header;
    // The gyroscope's file has no accelerometer to describe (described from column -1 before).
    EXPECT_FALSE(HasNote(source, "accelerometer '")) << header;
  }
}

TEST(ImuLogProbe, QuotedHeadersKeepTheirNames) {
  ImuLogSource source;
  const TriadLog log = ReadOk(
      "\"Time (s)\",\"Acceleration x (m/s^2)\",\"Acceleration y (m/s^2)\",\"Acceleration z "
      "(m/s^2)\"\n" +
          Rows(30, [](int, double t) { return StringPrintf("\"%.2f\",\"1\",\"2\",\"9.8\"\n", t); }),
      {}, &source);
  ExpectStillSensor(log, 30, 0.01, false);
  EXPECT_NE(source.layout.find("t = 'Time (s)'; accelerometer 'Acceleration x (m/s^2)'"),
            std::string::npos)
      << source.layout;
  EXPECT_EQ(source.accelerometer_unit, "m/s^2");
}

TEST(ImuLogProbe, RowsEndingInASeparatorTheHeaderLacks) {
  ImuLogSource source;
  const TriadLog log = ReadOk(
      "t,ax,ay,az\n" + Rows(30, [](int, double t) { return StringPrintf("%.2f,1,2,9.8,\n", t); }),
      {}, &source);
  ExpectStillSensor(log, 30, 0.01, false);
  EXPECT_TRUE(HasNote(source, "ends in a separator"));
}

TEST(ImuLogProbe, XsensSampleTimeFineIsInTicksOf100Microseconds) {
  const TriadLog log = ReadOk(
      "// General information:\n// Update rate: "
      "100.00Hz\nPacketCounter\tSampleTimeFine\tAcc_X\tAcc_Y\t"
      "Acc_Z\n" +
      Rows(30, [](int j, double) {
        return StringPrintf("%d\t%d\t1\t2\t9.8\n", 1000 + j, 123456 + 100 * j);
      }));
  ExpectStillSensor(log, 30, 0.01, false);  // read as 10 Hz (ms) before
}

TEST(ImuLogProbe, AStepTwoUnitsExplainEquallyIsAskedNotGuessed) {
  // 100 units a step: 10 Hz in ms or 10 kHz in us; neither is a usual IMU rate.
  const std::string message = Refusal("time,ax,ay,az\n" + Rows(30, [](int j, double) {
                                        return StringPrintf("%d,1,2,9.8\n", 100 * j);
                                      }));
  EXPECT_NE(message.find("give --time_unit=s, ms, us or ns"), std::string::npos) << message;
}

TEST(ImuLogProbe, BurstsOfHostStampsAskForTheRate) {
  // BLE: three samples stamped within 2 ms every 60 ms, Unix milliseconds; 50 Hz in truth.
  const std::string text =
      "timestamp,ax,ay,az\n" + Rows(300, [](int j, double) {
        return StringPrintf("%lld,1,2,9.8\n", 1732650000000LL + 60 * (j / 3) + (j % 3));
      });
  const std::string message = Refusal(text);
  EXPECT_NE(message.find("the time stamps come in bursts"), std::string::npos) << message;
  EXPECT_EQ(message.find("sample number"), std::string::npos) << message;
  ImuLogReadOptions options;  // the suggestion, followed
  const size_t at = message.find("--rate_hz=");
  ASSERT_NE(at, std::string::npos);
  options.rate_hz = std::stod(message.substr(at + 10));
  EXPECT_NEAR(options.rate_hz, 50.0, 0.5);
  ASSERT_EQ(ReadOk(text, options).size(), 300u);
}

TEST(ImuLogProbe, AWrongTimeUnitIsCorrected) {
  ImuLogReadOptions options;
  options.time_unit = "ms";  // the column is in microseconds
  const std::string message =
      Refusal("t,ax,ay,az\n" +
                  Rows(30, [](int j, double) { return StringPrintf("%d,1,2,9.8\n", 10000 * j); }),
              options);
  EXPECT_NE(message.find("give --time_unit=us"), std::string::npos) << message;
}

TEST(ImuLogProbe, ThreeUnnamedColumnsAskForTheRate) {
  const std::string message =
      Refusal(Rows(30, [](int, double) { return std::string("1 2 9.8\n"); }));
  EXPECT_NE(message.find("give --rate_hz=R"), std::string::npos) << message;
  EXPECT_EQ(message.find("az:4"), std::string::npos) << message;
}

TEST(ImuLogProbe, ARepeatedHeaderAndUtf16WithoutAMarkAreNamed) {
  const std::string joined =
      "t,ax,ay,az\n" + Rows(10, [](int, double t) { return StringPrintf("%.2f,1,2,9.8\n", t); }) +
      "t,ax,ay,az\n";
  EXPECT_NE(Refusal(joined).find("line 12 repeats the header of line 1"), std::string::npos)
      << Refusal(joined);
  const std::string utf16("t\0,\0a\0x\0\n\0", 10);
  EXPECT_NE(Refusal(utf16).find("UTF-16"), std::string::npos);
}

// Writes matio's `variables` (freed here) as a MAT file of `version`.
void WriteWithMatio(const std::string& path, mat_ft version,
                    std::initializer_list<matvar_t*> variables) {
  mat_t* file = Mat_CreateVer(path.c_str(), nullptr, version);
  ASSERT_NE(file, nullptr) << path;
  for (matvar_t* variable : variables) {
    ASSERT_NE(variable, nullptr);
    EXPECT_EQ(Mat_VarWrite(file, variable, MAT_COMPRESSION_NONE), 0) << variable->name;
    Mat_VarFree(variable);
  }
  Mat_Close(file);
}

// A rows x cols matio variable of `class_type`, its values copied.
template <typename T>
matvar_t* Variable(const char* name, matio_classes class_type, matio_types type, size_t rows,
                   size_t cols, std::vector<T> values) {
  size_t dims[2] = {rows, cols};
  return Mat_VarCreate(name, class_type, type, 2, dims, values.data(), 0);
}

// A logger's raw counts saved as integers (scipy.io.savemat of an int16 array, MATLAB's
// int32(...)): read as doubles, every value exactly, from version 5 and 7.3 files alike.
TEST(ImuLogLayouts, ReadsIntegerMatVariablesExactly) {
  testing::ScratchDir dir;
  std::vector<double> t;
  std::vector<int16_t> acc;  // 30 x 3, column-major: x counts from -32768 up, y 2048, z 32767
  std::vector<uint32_t> stamp_us;
  for (int j = 0; j < 30; ++j) t.push_back(0.01 * j);
  for (int j = 0; j < 30; ++j) acc.push_back(static_cast<int16_t>(-32768 + j));
  acc.insert(acc.end(), 30, 2048);
  acc.insert(acc.end(), 30, 32767);
  for (int j = 0; j < 30; ++j) stamp_us.push_back(4000000000u + 10000u * j);
  for (mat_ft version : {MAT_FT_MAT5, MAT_FT_MAT73}) {
    const std::string path = dir.File(version == MAT_FT_MAT5 ? "counts5.mat" : "counts73.mat");
    WriteWithMatio(path, version,
                   {Variable("t", MAT_C_DOUBLE, MAT_T_DOUBLE, 30, 1, t),
                    Variable("acc", MAT_C_INT16, MAT_T_INT16, 30, 3, acc)});
    TriadLog log;
    Status status = ReadImuLog(path, &log);
    ASSERT_TRUE(status.ok()) << status.message();
    ASSERT_EQ(log.size(), 30u);
    EXPECT_EQ(log.output[0][0], -32768.0);
    EXPECT_EQ(log.output[29][0], -32739.0);
    EXPECT_EQ(log.output[7][1], 2048.0);
    EXPECT_EQ(log.output[7][2], 32767.0);
    // Named in --columns, as a double would be; a uint32 time in microseconds beyond 2^31.
    const std::string named = dir.File(version == MAT_FT_MAT5 ? "named5.mat" : "named73.mat");
    WriteWithMatio(named, version,
                   {Variable("stamp", MAT_C_UINT32, MAT_T_UINT32, 30, 1, stamp_us),
                    Variable("counts", MAT_C_INT16, MAT_T_INT16, 30, 3, acc)});
    ImuLogReadOptions options;
    options.columns = "acc:counts,t:stamp";
    options.time_unit = "us";
    status = ReadImuLog(named, options, &log);
    ASSERT_TRUE(status.ok()) << status.message();
    EXPECT_NEAR(log.timestamp_s[29] - log.timestamp_s[0], 0.29, 1e-12);
    EXPECT_EQ(log.output[3][0], -32765.0);
  }
  // int64 nanoseconds since 1970 are beyond 2^53: a double would round them; refused, naming
  // the value and what to do.
  std::vector<int64_t> epoch_ns;
  for (int j = 0; j < 30; ++j) epoch_ns.push_back(1700000000000000001 + 10000000ll * j);
  const std::string epoch = dir.File("epoch.mat");
  WriteWithMatio(epoch, MAT_FT_MAT5,
                 {Variable("t", MAT_C_INT64, MAT_T_INT64, 30, 1, epoch_ns),
                  Variable("acc", MAT_C_INT16, MAT_T_INT16, 30, 3, acc)});
  TriadLog log;
  EXPECT_ERROR_CONTAINS(ReadImuLog(epoch, ImuLogReadOptions(), &log),
                        "variable 't' is int64 and its value 1700000000000000001 (element 1) is "
                        "beyond 2^53, where a double cannot hold every integer; subtract its "
                        "first value in MATLAB (x = double(x - x(1))) and save it again");
  // int64 time in microseconds, within 2^53, is read.
  for (int j = 0; j < 30; ++j) epoch_ns[j] = 10000 * j;
  WriteWithMatio(epoch, MAT_FT_MAT5,
                 {Variable("t_us", MAT_C_INT64, MAT_T_INT64, 30, 1, epoch_ns),
                  Variable("acc", MAT_C_INT16, MAT_T_INT16, 30, 3, acc)});
  const Status status = ReadImuLog(epoch, ImuLogReadOptions(), &log);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_DOUBLE_EQ(log.timestamp_s[29], 0.29);
}

// Variables a log cannot use are listed with their class, and one named in --columns is
// refused for what it is, not as absent.
TEST(ImuLogLayouts, NamesTheClassOfMatVariablesItCannotUse) {
  testing::ScratchDir dir;
  std::vector<double> t(30);
  for (int j = 0; j < 30; ++j) t[j] = 0.01 * j;
  for (mat_ft version : {MAT_FT_MAT5, MAT_FT_MAT73}) {
    const std::string path = dir.File(version == MAT_FT_MAT5 ? "labelled5.mat" : "labelled73.mat");
    const char* fields[] = {"acc", "temp"};
    size_t one[2] = {1, 1};
    matvar_t* imu = Mat_VarCreateStruct("imu", 2, one, fields, 2);
    Mat_VarSetStructFieldByName(
        imu, "acc", 0, Variable("acc", MAT_C_DOUBLE, MAT_T_DOUBLE, 1, 1, std::vector{1.0}));
    Mat_VarSetStructFieldByName(
        imu, "temp", 0, Variable("temp", MAT_C_DOUBLE, MAT_T_DOUBLE, 1, 1, std::vector{2.0}));
    WriteWithMatio(path, version,
                   {Variable("t", MAT_C_DOUBLE, MAT_T_DOUBLE, 30, 1, t),
                    Variable("name", MAT_C_CHAR, MAT_T_UINT8, 1, 5,
                             std::vector<char>{'h', 'e', 'l', 'l', 'o'}),
                    imu});
    TriadLog log;
    const Status listed = ReadImuLog(path, ImuLogReadOptions(), &log);
    EXPECT_ERROR_CONTAINS(listed, "no accelerometer among the variables (t (30x1), ");
    EXPECT_ERROR_CONTAINS(listed, "name (1x5 char)");  // version 7.3 lists by name
    EXPECT_ERROR_CONTAINS(listed, "imu (1x1 struct: acc, temp)");
    ImuLogReadOptions options;
    options.columns = "acc:name,t:t";
    EXPECT_ERROR_CONTAINS(ReadImuLog(path, options, &log),
                          "variable 'name' is a char array; expected a real numeric matrix");
    options.columns = "acc:imu,t:t";
    EXPECT_ERROR_CONTAINS(ReadImuLog(path, options, &log),
                          "variable 'imu' is a struct; expected a real numeric matrix (its fields: "
                          "acc, temp); save the fields as variables, e.g. acc = imu.acc; "
                          "save('log.mat', 'acc', ...)");
    options.columns = "acc:accel,t:t";
    EXPECT_ERROR_CONTAINS(ReadImuLog(path, options, &log), "no variable 'accel' in the file");
  }
}

}  // namespace
}  // namespace accelcal
