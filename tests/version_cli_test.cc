// --version: every binary says what it is, the version, the git commit it was built from and the
// build type (common/build_info.h), and exits 0.

#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "test_support.h"

namespace accelcal {
namespace {

TEST(VersionCli, EveryBinaryPrintsItsVersionCommitAndBuildType) {
  const std::regex line(
      "^[a-z_]+ version [0-9]+\\.[0-9]+\\.[0-9]+ \\(commit ([0-9a-f]{12}(-modified)?|unknown), "
      "[A-Za-z]+ build\\)\n");
  for (const char* binary : {"calibrate_imu", "apply", "linear_ls", "gyroscope_study", "analyze"}) {
    const testing::CommandResult result = testing::RunBinaryArgs(binary, {"--version"});
    EXPECT_EQ(result.exit_status, 0) << binary;
    EXPECT_TRUE(std::regex_search(result.stdout_text, line))
        << binary << ": " << result.stdout_text;
    EXPECT_EQ(result.stdout_text.rfind(std::string(binary) + " version ", 0), 0u) << binary;
  }
}

}  // namespace
}  // namespace accelcal
