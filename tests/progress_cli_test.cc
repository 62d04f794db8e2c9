// --progress on the binaries that run for a while: lines with the time left on stderr when
// asked, nothing when not, and stdout and the output files the same either way.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::RunBinaryArgs;
using testing::ScratchDir;

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) lines.push_back(line);
  return lines;
}

// min_samples on the simulated default, one design, one thread: 6000 Monte Carlo trials,
// several seconds, and no timing in its stdout or its JSON, so both compare byte for byte.
std::vector<std::string> MinSamplesArguments(const std::string& json, const std::string& mode) {
  return {"--design=uniform", "--repetitions=3000", "--threads=1", "--json=" + json,
          "--progress=" + mode};
}

TEST(ProgressBinary, AlwaysShowsTheTimeLeftOnStderrAndChangesNoOutput) {
  ScratchDir out;
  const CommandResult shown =
      RunBinaryArgs("min_samples", MinSamplesArguments(out.File("shown.json"), "always"));
  ASSERT_EQ(shown.exit_status, 0) << shown.stderr_text;
  const CommandResult quiet =
      RunBinaryArgs("min_samples", MinSamplesArguments(out.File("quiet.json"), "never"));
  ASSERT_EQ(quiet.exit_status, 0) << quiet.stderr_text;

  EXPECT_EQ(shown.stdout_text, quiet.stdout_text);
  // The same JSON but for the command line that wrote it.
  nlohmann::json shown_json = nlohmann::json::parse(testing::ReadText(out.File("shown.json")));
  nlohmann::json quiet_json = nlohmann::json::parse(testing::ReadText(out.File("quiet.json")));
  EXPECT_NE(shown_json["command_line"], quiet_json["command_line"]);
  shown_json.erase("command_line");
  quiet_json.erase("command_line");
  EXPECT_EQ(shown_json.dump(), quiet_json.dump());
  EXPECT_EQ(quiet.stderr_text, "");

  // Not a terminal: whole lines, no '\r'; at least one estimate before the last line.
  EXPECT_EQ(shown.stderr_text.find('\r'), std::string::npos) << shown.stderr_text;
  const std::vector<std::string> lines = Lines(shown.stderr_text);
  ASSERT_GE(lines.size(), 2u) << shown.stderr_text;
  for (size_t i = 0; i + 1 < lines.size(); ++i) {
    EXPECT_EQ(lines[i].rfind("min_samples: ", 0), 0u) << lines[i];
    EXPECT_NE(lines[i].find(" Monte Carlo trials ("), std::string::npos) << lines[i];
    EXPECT_NE(lines[i].find(" elapsed, about "), std::string::npos) << lines[i];
    EXPECT_NE(lines[i].find(" left"), std::string::npos) << lines[i];
  }
  EXPECT_EQ(lines.back().rfind("min_samples: 6000/6000 Monte Carlo trials (100%), done in ", 0), 0u)
      << lines.back();
}

// Into a file, "auto" (the default) shows nothing: logs of scripted runs stay as they were.
TEST(ProgressBinary, AutoShowsNothingWhenStderrIsNotATerminal) {
  ScratchDir out;
  const CommandResult result =
      RunBinaryArgs("coverage", {"--trials=200", "--effect_trials=10", "--progress=auto"});
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_EQ(result.stderr_text, "");
  EXPECT_NE(result.stdout_text.find("accelcal coverage:"), std::string::npos);
}

// analyze names its five steps as each starts and ends.
TEST(ProgressBinary, AnalyzeNamesItsSteps) {
  ScratchDir out;
  const CommandResult result = RunBinaryArgs(
      "analyze",
      {"--out_dir=" + out.File("report"), "--python=/nonexistent/python", "--progress=always"});
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::vector<std::string> lines = Lines(result.stderr_text);
  ASSERT_EQ(lines.size(), 10u) << result.stderr_text;
  for (int step = 1; step <= 5; ++step) {
    const std::string prefix = "analyze: step " + std::to_string(step) + "/5 ";
    EXPECT_EQ(lines[2 * step - 2].rfind(prefix, 0), 0u) << lines[2 * step - 2];
    EXPECT_EQ(lines[2 * step - 1].rfind(prefix, 0), 0u) << lines[2 * step - 1];
    EXPECT_NE(lines[2 * step - 1].find(", done in "), std::string::npos) << lines[2 * step - 1];
  }
  EXPECT_NE(lines[6].find("min_samples"), std::string::npos) << lines[6];
}

TEST(ProgressBinary, AnUnknownModeIsBadInput) {
  // Refused before any work or output.
  for (const std::string binary : {"power", "coverage", "min_samples", "null_rate", "analyze"}) {
    testing::ExpectBadInputContract(RunBinaryArgs(binary, {"--progress=sometimes"}), binary,
                                    "--progress must be auto, always or never, got 'sometimes'");
  }
}

}  // namespace
}  // namespace accelcal
