// allan on long text logs (issue 36, item 2): read in passes over a temporary binary copy of the
// samples, it prints and writes what the whole-log path (--stream=false) does, to the digit, on
// a simulated hand-held log that spans several of the reader's batches (every pose, the longest,
// given segments) and on imu_tk's Xsens log; its refusals are the whole-log path's, one line,
// exit status 2, no output, and no temporary file left in $TMPDIR.

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "hand_held_session.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::ExpectBadInputContract;
using testing::RunCommand;

// A hand-held session of `holds` holds as imu_tk's text, with a gap when asked.
std::string HandHeldLog(int holds, uint64_t seed, size_t gap_first = 0, size_t gap_count = 0) {
  return testing::ImuTkText(testing::HandHeldSession(seed, holds).log, gap_first, gap_count);
}

// `text` without its lines naming the command line or a duration (they differ by the flags).
std::string Stable(const std::string& text) {
  std::string kept;
  size_t begin = 0;
  while (begin < text.size()) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(begin, end - begin);
    if (line.find("command") == std::string::npos && line.find("seconds") == std::string::npos)
      kept += line + "\n";
    begin = end + 1;
  }
  return kept;
}

// allan with `flags`, streamed (default) or whole, $TMPDIR a folder of its own that must be empty
// afterwards; *json the JSON it wrote ("" when none).
CommandResult Allan(const std::string& flags, bool stream, std::string* json) {
  testing::ScratchDir tmp, out;
  const std::string json_path = out.File("allan.json");
  const CommandResult result =
      RunCommand("TMPDIR='" + tmp.path() + "' '" + testing::BinaryPath("allan") + "' " + flags +
                 " --json=" + json_path + (stream ? "" : " --stream=false"));
  EXPECT_TRUE(testing::FilesIn(tmp.path()).empty()) << "a temporary file was left in $TMPDIR";
  *json = testing::FilesIn(out.path()).empty() ? "" : testing::ReadText(json_path);
  return result;
}

// Streamed and whole, the same exit status, stdout, stderr and JSON; the exit status.
int ExpectSameBothWays(const std::string& flags) {
  std::string streamed_json, whole_json;
  const CommandResult streamed = Allan(flags, true, &streamed_json);
  const CommandResult whole = Allan(flags, false, &whole_json);
  EXPECT_EQ(streamed.exit_status, whole.exit_status) << flags << ": " << streamed.stderr_text;
  EXPECT_EQ(streamed.stdout_text, whole.stdout_text) << flags;
  EXPECT_EQ(streamed.stderr_text, whole.stderr_text) << flags;
  EXPECT_TRUE(Stable(streamed_json) == Stable(whole_json)) << flags << ": the JSON differs";
  return streamed.exit_status;
}

// 420 holds: some 230,000 samples, four of the reader's batches of 65,536.
TEST(AllanStreamCli, StreamedResultsAreTheWholeLogPaths) {
  testing::ScratchDir scratch;
  const std::string log = scratch.Write("hand_held.txt", HandHeldLog(420, 5));
  const std::string common = "--log=" + log + " --unit=count --bootstrap=100";
  EXPECT_EQ(ExpectSameBothWays(common + " --static=all"), 0);
  EXPECT_EQ(ExpectSameBothWays(common + " --static=longest --gain=0.0024"), 0);
  EXPECT_EQ(ExpectSameBothWays(common + " --segment=10:400,1000:1300"), 0);
}

// A still log, one rest of 80,000 samples (issue 49, item 1): one run of candidate windows longer
// than the streamed detector holds, one segment longer than the bootstrap simulates whole; the
// streamed path gives the whole-log path's results. --progress=always names the five steps on
// stderr and changes nothing on stdout.
TEST(AllanStreamCli, AStillLogOfOneLongRestIsTheWholeLogPaths) {
  testing::ScratchDir scratch;
  RandomSource random(49);
  TriadHold rest;
  rest.direction = {0.0, 0.0, 1.0};
  rest.duration_s = 800.0;
  const TriadLog still = SimulateTriadSession(testing::HandHeldTriad(), {rest}, &random).log;
  ASSERT_GT(still.size(), 70000u);
  const std::string log = scratch.Write("still.txt", testing::ImuTkText(still));
  const std::string flags = "--log=" + log + " --unit=count --bootstrap=100";
  EXPECT_EQ(ExpectSameBothWays(flags), 0);
  std::string json;
  const CommandResult quiet = Allan(flags, true, &json);
  const CommandResult shown = Allan(flags + " --progress=always", true, &json);
  ASSERT_EQ(shown.exit_status, 0) << shown.stderr_text;
  EXPECT_EQ(shown.stdout_text, quiet.stdout_text);
  EXPECT_NE(quiet.stdout_text.find("1 static segment"), std::string::npos) << quiet.stdout_text;
  EXPECT_EQ(quiet.stderr_text, "");
  for (int step = 1; step <= 5; ++step) {
    EXPECT_NE(shown.stderr_text.find(StringPrintf("allan: step %d/5 ", step)), std::string::npos)
        << shown.stderr_text;
  }
}

// $TMPDIR that cannot hold the spool (here: a folder that does not exist): the log is read whole,
// the results are the same, and a note says so and what to do (issue 45: it was silent).
TEST(AllanStreamCli, SaysWhenTheSpoolCannotBeWrittenAndReadsTheLogWhole) {
  testing::ScratchDir scratch;
  const std::string log = scratch.Write("hand_held.txt", HandHeldLog(60, 8));
  const std::string flags = " --log=" + log + " --unit=count --bootstrap=100";
  const CommandResult spooled = RunCommand("'" + testing::BinaryPath("allan") + "'" + flags);
  const CommandResult whole = RunCommand("TMPDIR='" + scratch.path() + "/missing' '" +
                                         testing::BinaryPath("allan") + "'" + flags);
  ASSERT_EQ(spooled.exit_status, 0) << spooled.stderr_text;
  EXPECT_EQ(whole.exit_status, 0) << whole.stderr_text;
  EXPECT_EQ(whole.stdout_text, spooled.stdout_text);
  EXPECT_EQ(spooled.stderr_text.find("read whole into memory"), std::string::npos);
  EXPECT_NE(whole.stderr_text.find("allan: note: the log is read whole into memory"),
            std::string::npos)
      << whole.stderr_text;
  EXPECT_NE(whole.stderr_text.find("set TMPDIR to a writable folder"), std::string::npos);
}

TEST(AllanStreamCli, StreamedResultsAreTheWholeLogPathsOnTheXsensLog) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  EXPECT_EQ(ExpectSameBothWays("--log=" + dir +
                               "/xsens_acc.mat --unit=count --static=all --bootstrap=100"),
            0);
}

// Refused both ways with the same line: a pause inside a given segment, a log in counts said to
// be in m/s^2, a damaged line far into the log; and a log that never rests, whose detector the
// streamed path hands to the whole-log path, with --segment gives the same results.
TEST(AllanStreamCli, RefusalsAreTheWholeLogPaths) {
  testing::ScratchDir scratch;
  const std::string gap = scratch.Write("gap.txt", HandHeldLog(60, 6, 10000, 50));
  const std::string log = scratch.Write("log.txt", HandHeldLog(60, 7));
  std::string damaged = HandHeldLog(60, 8);
  const size_t late = damaged.find('\n', damaged.size() - 2000);
  damaged.insert(late + 1, "330.0 32808 x32743 32778\n");
  const std::string bad = scratch.Write("bad.txt", damaged);
  struct Case {
    std::string flags;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"--log=" + gap + " --segment=50:150", "an Allan variance needs uniform sampling"},
      {"--log=" + log + " --unit=m/s^2", "not about 9.8 as 1 g is in m/s^2"},
      {"--log=" + bad, bad + ": line"},
  };
  for (const Case& c : cases) {
    std::string streamed_json, whole_json;
    const CommandResult streamed = Allan(c.flags + " --bootstrap=100", true, &streamed_json);
    const CommandResult whole = Allan(c.flags + " --bootstrap=100", false, &whole_json);
    ExpectBadInputContract(streamed, "allan", c.says);
    EXPECT_EQ(streamed.stderr_text, whole.stderr_text) << c.flags;
    EXPECT_TRUE(streamed_json.empty()) << c.flags;
  }
  // A log that never rests: the streamed path hands it to the whole-log path.
  const std::string text = testing::ImuTkText(testing::NeverRestingLog(31));
  const std::string never_rests = scratch.Write("moving.txt", text);
  std::printf("[ moving    ] exit status %d both ways\n",
              ExpectSameBothWays("--log=" + never_rests +
                                 " --unit=count --bootstrap=100 "
                                 "--segment=5:60"));
}

}  // namespace
}  // namespace accelcal
