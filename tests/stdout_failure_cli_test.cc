// A failed write to stdout ends the run with one line on stderr and exit status 2 (issue 35,
// item 3): the printed table is the only result of a run without --json, so losing it on a full
// disk (/dev/full: ENOSPC) or a closed pipe (EPIPE) must not look like success. Each binary
// runs once with stdout on /dev/full and once into a pipe whose reader is gone; the same runs
// with stdout on a file succeed.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::ReadText;
using testing::RunBinaryArgs;
using testing::ScratchDir;

// Runs build/bin/<binary> with `arguments`, stdout into a pipe whose read end is closed before
// the binary starts (every write fails with EPIPE, or kills by SIGPIPE), stderr captured.
CommandResult RunIntoClosedPipe(const std::string& binary,
                                const std::vector<std::string>& arguments) {
  ScratchDir capture;
  CommandResult result;
  int pipe_ends[2];
  if (pipe(pipe_ends) != 0) {
    ADD_FAILURE() << "pipe() failed";
    return result;
  }
  close(pipe_ends[0]);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_ends[1], STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, capture.File("stderr").c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0600);
  const int status = testing::SpawnBinaryWithActions(binary, arguments, &actions);
  posix_spawn_file_actions_destroy(&actions);
  close(pipe_ends[1]);
  result.exit_status = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.stderr_text = ReadText(capture.File("stderr"));
  if (status != -1 && WIFSIGNALED(status))
    result.stderr_text += "[killed by signal " + std::to_string(WTERMSIG(status)) + "]";
  return result;
}

// The binary succeeds with stdout on a file, and fails in one line, exit status 2, on /dev/full
// and on a closed pipe.
void ExpectStdoutFailureIsAnError(const std::string& binary,
                                  const std::vector<std::string>& arguments) {
  const CommandResult ok = RunBinaryArgs(binary, arguments);
  ASSERT_EQ(ok.exit_status, 0) << ok.stderr_text;
  ASSERT_FALSE(ok.stdout_text.empty());

  ScratchDir capture;
  const int status = testing::SpawnBinary(binary, arguments, "/dev/full", capture.File("stderr"));
  const std::string full_stderr = ReadText(capture.File("stderr"));
  ASSERT_TRUE(WIFEXITED(status)) << binary << " on /dev/full: " << full_stderr;
  EXPECT_EQ(WEXITSTATUS(status), 2) << binary << " on /dev/full: " << full_stderr;
  // The last line says it (a run may print notes on stderr before).
  const std::string last_line =
      full_stderr.substr(full_stderr.rfind('\n', full_stderr.size() - 2) + 1);
  EXPECT_EQ(last_line.rfind(binary + ": error: writing the results to stdout failed", 0), 0u)
      << full_stderr;
  EXPECT_NE(last_line.find("No space left on device"), std::string::npos) << full_stderr;

  const CommandResult piped = RunIntoClosedPipe(binary, arguments);
  EXPECT_EQ(piped.exit_status, 2) << binary << " into a closed pipe: " << piped.stderr_text;
  EXPECT_NE(piped.stderr_text.find(binary + ": error: writing the results to stdout failed"),
            std::string::npos)
      << piped.stderr_text;
  EXPECT_NE(piped.stderr_text.find("Broken pipe"), std::string::npos) << piped.stderr_text;
}

TEST(StdoutFailure, LinearLsSaysSoAndExitsWithStatus2) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ExpectStdoutFailureIsAnError("linear_ls", {"--data_dir=" + dir});
}

TEST(StdoutFailure, ApplySaysSoAndExitsWithStatus2) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir scratch;
  const std::string calibration = scratch.File("calibration.json");
  const CommandResult calibrated =
      RunBinaryArgs("calibrate", {"--data_dir=" + dir, "--calibration_out=" + calibration});
  ASSERT_EQ(calibrated.exit_status, 0) << calibrated.stderr_text;
  const std::string log = scratch.Write("log.csv", "t,ax,ay\n0,1,2\n0.01,1,2\n0.02,1,2\n");
  ExpectStdoutFailureIsAnError("apply", {"--calibration=" + calibration, "--in=" + log,
                                         "--out=" + scratch.File("corrected.csv")});
}

TEST(StdoutFailure, CalibrateImuSaysSoAndExitsWithStatus2) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  ExpectStdoutFailureIsAnError("calibrate_imu",
                               {"--log=" + dir + "/xsens_acc.mat", "--g=9.81744", "--mode=imu_tk",
                                "--init_rest_s=50", "--initial_offset=32768"});
}

}  // namespace
}  // namespace accelcal
