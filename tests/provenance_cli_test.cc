// Every binary says where its data came from, first on stdout ("data: ...") and in its JSON
// (source, input_files with SHA-256, command_line, accelcal_version), with and without
// --data_dir, so a simulated result can never pass as a measured one (issue 18).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::RunBinary;
using testing::ScratchDir;

struct Case {
  const char* binary;
  const char* flags;   // besides --data_dir and the output
  const char* output;  // "json": --json=FILE; otherwise the JSON file inside --out_dir
  size_t files_read;   // from a course-layout folder
};

// Small settings: the provenance does not depend on the work done.
const Case kCases[] = {
    {"linear_ls", "", "json", 2},  // the tilt test and the stated noise only
    {"trajectory", "", "json", 4},
    {"joint", "", "json", 4},
    {"discover", "--folds=0", "json", 4},
    {"min_samples", "--repetitions=0 --design=uniform", "json", 4},
    {"analyze", "--python=/nonexistent", "results.json", 4},
    {"simulate", "", "truth.json", 0},
    {"coverage", "--trials=10 --effect_trials=0 --set=tilt_samples=500", "json", 0},
    {"power", "--trials=10 --sizes=3 --set=tilt_samples=500", "json", 0},
    {"null_rate", "--datasets=10 --designs=course --noise_factors=1 --alphas=0.01", "json", 0},
};

bool ReadsMeasuredData(const std::string& binary) {
  return binary != "simulate" && binary != "coverage" && binary != "power" && binary != "null_rate";
}
bool Simulates(const std::string& binary) { return binary != "trajectory"; }

nlohmann::json RunAndReadJson(const Case& c, const std::string& data_flag, std::string* stdout_text,
                              std::string* report_md = nullptr) {
  ScratchDir scratch;
  const std::string output = std::string(c.output) == "json"
                                 ? "--json='" + scratch.File("out.json") + "'"
                                 : "--out_dir='" + scratch.File("out") + "'";
  const CommandResult result = RunBinary(c.binary, data_flag + " " + c.flags + " " + output);
  EXPECT_EQ(result.exit_status, 0) << c.binary << ": " << result.stderr_text;
  *stdout_text = result.stdout_text;
  if (report_md != nullptr) *report_md = testing::ReadText(scratch.File("out") + "/report.md");
  const std::string json_path = std::string(c.output) == "json"
                                    ? scratch.File("out.json")
                                    : scratch.File("out") + "/" + c.output;
  return nlohmann::json::parse(testing::ReadText(json_path), nullptr, false);
}

void ExpectCommandLine(const nlohmann::json& json, const std::string& binary) {
  ASSERT_TRUE(json.contains("command_line"));
  EXPECT_EQ(json["command_line"].get<std::string>().rfind(binary + " ", 0), 0u)
      << json["command_line"];
  EXPECT_TRUE(json["accelcal_version"].is_string());
}

TEST(Provenance, EveryBinaryOnMeasuredDataNamesTheFolderAndTheFilesChecksums) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  for (const Case& c : kCases) {
    if (!ReadsMeasuredData(c.binary)) continue;
    SCOPED_TRACE(c.binary);
    std::string stdout_text, report_md;
    const bool report = std::string(c.output) == "results.json";
    const nlohmann::json json =
        RunAndReadJson(c, "--data_dir='" + dir + "'", &stdout_text, report ? &report_md : nullptr);
    ASSERT_FALSE(json.is_discarded());
    EXPECT_EQ(stdout_text.substr(0, stdout_text.find('\n')),
              "data: " + dir + " (" + std::to_string(c.files_read) + " files)");
    EXPECT_EQ(json["source"]["kind"], "measured");
    EXPECT_EQ(json["source"]["data_dir"], dir);
    ASSERT_EQ(json["input_files"].size(), c.files_read) << json["input_files"];
    for (const auto& [role, file] : json["input_files"].items()) {
      const std::string path = file["path"];
      const CommandResult sha256sum = testing::RunCommand("sha256sum '" + path + "'");
      EXPECT_EQ(file["sha256"], sha256sum.stdout_text.substr(0, 64)) << role;
      // analyze's report says it too, in its provenance section.
      if (report) {
        EXPECT_NE(report_md.find("| " + role + " | " + path + " | "), std::string::npos);
        EXPECT_NE(report_md.find(sha256sum.stdout_text.substr(0, 64)), std::string::npos);
      }
    }
    ExpectCommandLine(json, c.binary);
  }
}

TEST(Provenance, EveryBinaryOnSimulatedDataSaysSoWithScenarioSeedAndWhatIsHidden) {
  for (const Case& c : kCases) {
    if (!Simulates(c.binary)) continue;
    SCOPED_TRACE(c.binary);
    std::string stdout_text;
    // analyze's default simulation hides angle_offset; --set= hides nothing.
    const std::string hide_nothing = std::string(c.binary) == "analyze" ? " --set=" : "";
    const nlohmann::json json = RunAndReadJson(c, "--seed=3" + hide_nothing, &stdout_text);
    ASSERT_FALSE(json.is_discarded());
    EXPECT_EQ(stdout_text.substr(0, stdout_text.find('\n')),
              "data: simulated, scenario tp2-2018, seed 3, nothing hidden beyond the baseline");
    EXPECT_EQ(json["source"]["kind"], "simulated");
    EXPECT_EQ(json["source"]["scenario"], "tp2-2018");
    EXPECT_EQ(json["source"]["seed"], 3);
    EXPECT_TRUE(json["input_files"].empty()) << json["input_files"];
    ExpectCommandLine(json, c.binary);
  }
}

TEST(Provenance, AHiddenEffectIsNamedFirst) {
  for (const char* binary : {"linear_ls", "joint", "discover", "simulate"}) {
    SCOPED_TRACE(binary);
    for (const Case& c : kCases) {
      if (std::string(c.binary) != binary) continue;
      std::string stdout_text;
      const nlohmann::json json = RunAndReadJson(c, "--set=angle_offset=0.004", &stdout_text);
      EXPECT_EQ(stdout_text.substr(0, stdout_text.find('\n')),
                "data: simulated, scenario tp2-2018, seed 1, hidden angle_offset=0.004");
      EXPECT_EQ(json["source"]["hidden"]["angle_offset"], 0.004);
    }
  }
}

}  // namespace
}  // namespace accelcal
