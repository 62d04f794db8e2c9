// A refused run prints nothing on stdout: the outputs and the inputs are checked before any
// work, so a person never reads a table whose JSON was then refused (issue 18). The BadFlags
// cases check stderr and the exit status; these check stdout as well.

#include <gtest/gtest.h>

#include <string>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::RunBinary;
using testing::ScratchDir;

TEST(LinearLsBinary, AnUnwritableJsonIsRefusedBeforeTheTableIsPrinted) {
  for (const std::string data : {std::string(), std::string("course")}) {
    std::string flags = "--json=/unwritable/x.json";
    if (!data.empty()) {
      const std::string dir = testing::CourseDataDir();
      if (dir.empty()) continue;
      flags += " --data_dir='" + dir + "'";
    }
    SCOPED_TRACE(flags);
    const CommandResult result = RunBinary("linear_ls", flags);
    EXPECT_EQ(result.exit_status, 2);
    EXPECT_EQ(result.stdout_text, "");
    EXPECT_EQ(testing::CountLines(result.stderr_text), 1) << result.stderr_text;
    EXPECT_NE(result.stderr_text.find("/unwritable"), std::string::npos) << result.stderr_text;
  }
}

TEST(LinearLsBinary, ADataDirThatIsAFileIsSaidToBeAFile) {
  ScratchDir scratch;
  const std::string file = scratch.Write("datos.txt", "not a folder\n");
  const CommandResult result = RunBinary("linear_ls", "--data_dir='" + file + "'");
  EXPECT_EQ(result.exit_status, 2);
  EXPECT_EQ(result.stdout_text, "");
  EXPECT_EQ(testing::CountLines(result.stderr_text), 1) << result.stderr_text;
  EXPECT_NE(result.stderr_text.find(file + ": is a file, not a folder"), std::string::npos)
      << result.stderr_text;
  EXPECT_EQ(result.stderr_text.find("no such"), std::string::npos) << result.stderr_text;
}

}  // namespace
}  // namespace accelcal
