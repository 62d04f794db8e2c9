// The triad log readers (io/imu_log.h): both layouts, streamed and whole, and their refusals.

#include "io/imu_log.h"

#include <gtest/gtest.h>

#include <string>

#include "common/format.h"
#include "test_support.h"

namespace accelcal {
namespace {

std::string Refusal(const std::string& text, ImuLogLayout layout) {
  TriadLog log;
  const Status status = ParseImuLog(text, layout, &log);
  EXPECT_FALSE(status.ok()) << text;
  return status.message();
}

constexpr ImuLogLayout kAscii = ImuLogLayout::kWhitespace;
constexpr ImuLogLayout kCsv = ImuLogLayout::kCsv;

TEST(ImuLog, ChoosesTheLayoutByTheFileName) {
  EXPECT_EQ(ImuLogLayoutOf("session.CSV"), kCsv);
  EXPECT_EQ(ImuLogLayoutOf("xsens_acc.mat"), kAscii);
  EXPECT_EQ(ImuLogLayoutOf("log.txt"), kAscii);
}

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
  const std::string message = Refusal("0.00 1 2 3\n0.01 1 2\n", kAscii);
  EXPECT_NE(message.find("line 2: 3 column(s), expected 4"), std::string::npos) << message;
  const std::string commas = Refusal("0.00,1,2,3\n", kAscii);
  EXPECT_NE(commas.find("*.csv"), std::string::npos) << commas;
  const std::string csv = Refusal("t_s,acc_x,acc_y,acc_z\n0.00,1,2\n", kCsv);
  EXPECT_NE(csv.find("line 2: 3 fields, expected 4"), std::string::npos) << csv;
}

TEST(ImuLog, RefusesAWrongCsvHeader) {
  const std::string message = Refusal("t,ax,ay,az\n0,1,2,3\n", kCsv);
  EXPECT_NE(message.find("expected 't_s,acc_x,acc_y,acc_z'"), std::string::npos) << message;
}

TEST(ImuLog, RefusesValuesThatAreNotFinite) {
  const std::string message = Refusal("0.00 1 2 3\n0.01 1 nan 3\n", kAscii);
  EXPECT_NE(message.find("line 2, column 3 (y): 'nan' is not a finite number"), std::string::npos)
      << message;
  const std::string text = Refusal("0.00 1 2 3\n0.01 1 abc 3\n", kAscii);
  EXPECT_NE(text.find("'abc' is not a number"), std::string::npos) << text;
  const std::string csv = Refusal("t_s,acc_x,acc_y,acc_z\n0,1,2,inf\n", kCsv);
  EXPECT_NE(csv.find("not a finite number"), std::string::npos) << csv;
}

TEST(ImuLog, RefusesTimeThatDoesNotIncrease) {
  const std::string message = Refusal("0.00 1 2 3\n0.01 1 2 3\n0.01 1 2 3\n", kAscii);
  EXPECT_NE(message.find("line 3: time 0.01 s does not increase"), std::string::npos) << message;
}

TEST(ImuLog, RefusesATimeAxisInMilliseconds) {
  const std::string message = Refusal("0 1 2 3\n10 1 2 3\n20 1 2 3\n", kAscii);
  EXPECT_NE(message.find("milliseconds"), std::string::npos) << message;
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
  EXPECT_EQ(status.message().rfind(path + ": line 2, column 4 (z)", 0), 0u) << status.message();
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
  const Status status = StreamImuLog(path, 64, [&](const TriadLog& batch) {
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

}  // namespace
}  // namespace accelcal
