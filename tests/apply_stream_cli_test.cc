// apply on long text logs (issue 36, item 2): the streamed correction writes, byte for byte,
// what the whole-log path writes, over a log that spans several of the reader's batches and
// needs the median's extra pass; a bad line far into the log, or a log refused on its median,
// leaves no output and no temporary file.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/format.h"
#include "gyroscope_calibration_example.h"
#include "io/calibration_file.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::ExpectBadInputContract;
using testing::RunBinary;

// The example triad (415 counts per m/s^2 about offsets near 32768) at rest in slowly turning
// directions, 100 Hz, with a deterministic noise of a few counts that is not an integer (so that
// the magnitudes are nearly all distinct), imu_tk's layout `t x y z`. Line `bad_line` (from 1),
// when given, is damaged.
std::string Log(int samples, int bad_line = 0) {
  std::string text;
  text.reserve(static_cast<size_t>(samples) * 48);
  const double offset[3] = {32808.0, 32743.0, 32778.0};
  for (int j = 0; j < samples; ++j) {
    if (j + 1 == bad_line) {
      text += RoundTripDouble(0.01 * (j + 1)) + " 32808 x32743 32778\n";
      continue;
    }
    const double angle = 1e-4 * j;
    const double force[3] = {9.81 * std::sin(angle) * 0.6, 9.81 * std::cos(angle) * 0.6,
                             9.81 * 0.8};
    text += RoundTripDouble(0.01 * (j + 1));
    for (int k = 0; k < 3; ++k) {
      const double noise = 3.0 * std::sin(12.9898 * j + 78.233 * k);
      text += " " + StringPrintf("%.3f", offset[k] + 415.0 * force[k] + noise);
    }
    text += "\n";
  }
  return text;
}

std::string WriteCalibration(const testing::ScratchDir& scratch) {
  return scratch.Write("cal.json", CalibrationJson(testing::ExampleTriadRecord()).dump(2) + "\n");
}

// The text without its '# command:' line (it names the flags, which differ).
std::string WithoutCommandLine(const std::string& text) {
  const size_t start = text.find("# command: ");
  if (start == std::string::npos) return text;
  return text.substr(0, start) + text.substr(text.find('\n', start) + 1);
}

// 300,000 samples: five of the reader's batches of 65,536 and many of the writer's blocks
// (tests/streaming_rank_test.cc checks the median's further passes). Streamed and read whole,
// the same bytes and the same summary.
TEST(ApplyStreamCli, StreamedOutputIsByteIdenticalToTheWholeLogPath) {
  testing::ScratchDir scratch;
  const std::string cal = WriteCalibration(scratch);
  const std::string in = scratch.Write("run.txt", Log(300000));
  const std::string streamed = scratch.File("streamed.csv");
  const std::string whole = scratch.File("whole.csv");
  const testing::CommandResult a =
      RunBinary("apply", "--calibration=" + cal + " --in=" + in + " --out=" + streamed);
  ASSERT_EQ(a.exit_status, 0) << a.stderr_text;
  const testing::CommandResult b =
      RunBinary("apply", "--stream=false --calibration=" + cal + " --in=" + in + " --out=" + whole);
  ASSERT_EQ(b.exit_status, 0) << b.stderr_text;
  std::string summary = a.stdout_text;
  const size_t named = summary.find(streamed);
  ASSERT_NE(named, std::string::npos) << summary;
  EXPECT_EQ(summary.replace(named, streamed.size(), whole), b.stdout_text);
  EXPECT_EQ(a.stderr_text, b.stderr_text);
  EXPECT_NE(a.stdout_text.find("300000 triad samples corrected"), std::string::npos)
      << a.stdout_text;
  const std::string streamed_text = testing::ReadText(streamed);
  const std::string whole_text = testing::ReadText(whole);
  ASSERT_GT(streamed_text.size(), 30000000u);
  EXPECT_TRUE(WithoutCommandLine(streamed_text) == WithoutCommandLine(whole_text))
      << "the streamed output differs from the whole-log path's";
}

// A bad value on line 290,000 of 300,000: exit status 2, one line naming the file and the line,
// no output and no temporary file, though most of the output had been written.
TEST(ApplyStreamCli, ABadLineLateInALongLogLeavesNothing) {
  testing::ScratchDir scratch;
  const std::string cal = WriteCalibration(scratch);
  testing::ScratchDir input;
  const std::string in = input.Write("run.txt", Log(300000, 290000));
  const std::string out = scratch.File("corrected.csv");
  const testing::CommandResult applied =
      RunBinary("apply", "--calibration=" + cal + " --in=" + in + " --out=" + out);
  ExpectBadInputContract(applied, "apply", in + ": line 290000");
  EXPECT_EQ(testing::FilesIn(scratch.path()), std::vector<std::string>{"cal.json"});
}

// A log in another unit than the calibration's (counts halved): refused on its median |a|, the
// median stated as the whole-log path states it, nothing written.
TEST(ApplyStreamCli, AMedianRefusalSaysWhatTheWholeLogPathSays) {
  testing::ScratchDir scratch;
  const std::string cal = WriteCalibration(scratch);
  std::string text;
  for (int j = 0; j < 200000; ++j) {
    text += RoundTripDouble(0.01 * (j + 1)) + " " +
            StringPrintf("%.3f %.3f %.3f\n", 32808.0 + 0.5 * j / 200000.0, 32743.0, 32778.0);
  }
  testing::ScratchDir input;
  const std::string in = input.Write("run.txt", text);
  const std::string out = scratch.File("corrected.csv");
  const testing::CommandResult streamed =
      RunBinary("apply", "--calibration=" + cal + " --in=" + in + " --out=" + out);
  ExpectBadInputContract(streamed, "apply", "the log's median |a| is");
  const testing::CommandResult whole =
      RunBinary("apply", "--stream=false --calibration=" + cal + " --in=" + in + " --out=" + out);
  EXPECT_EQ(streamed.stderr_text, whole.stderr_text);
  EXPECT_EQ(testing::FilesIn(scratch.path()), std::vector<std::string>{"cal.json"});
}

}  // namespace
}  // namespace accelcal
