// The simulate and coverage binaries as a user runs them: deterministic files for a
// seed, the CSV layout, truth.json, and the bad-input contract.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::RunCommand;
using testing::ScratchDir;

using testing::RunBinary;

TEST(SimulateBinary, SameSeedSameBytesAndTheTruthIsWrittenBeside) {
  ScratchDir scratch;
  const std::string a = scratch.File("a");
  const std::string b = scratch.File("b");
  ASSERT_EQ(
      RunBinary("simulate", "--out_dir='" + a + "' --seed=11 --set=bias_drift_y=0.05").exit_status,
      0);
  ASSERT_EQ(
      RunBinary("simulate", "--out_dir='" + b + "' --seed=11 --set=bias_drift_y=0.05").exit_status,
      0);
  for (const char* file : {"ensayo.mat", "acel.mat", "puntos.mat", "datos.txt"}) {
    const std::string first = testing::ReadText(a + "/" + file);
    EXPECT_FALSE(first.empty()) << file;
    EXPECT_EQ(first, testing::ReadText(b + "/" + file)) << file;
  }
  // truth.json too, but for the command line that made it (its --out_dir differs).
  nlohmann::json truth_a = nlohmann::json::parse(testing::ReadText(a + "/truth.json"));
  nlohmann::json truth_b = nlohmann::json::parse(testing::ReadText(b + "/truth.json"));
  truth_a.erase("command_line");
  truth_b.erase("command_line");
  EXPECT_EQ(truth_a, truth_b);
  const nlohmann::json truth = nlohmann::json::parse(testing::ReadText(a + "/truth.json"));
  EXPECT_EQ(truth["parameters"]["bias_drift_y"].get<double>(), 0.05);
  EXPECT_EQ(truth["parameters"]["bias_x"].get<double>(), 0.07667);
  EXPECT_EQ(truth["reached_landmark"], "C");
  EXPECT_EQ(truth["seed"].get<int>(), 11);
  // A different seed, different noise.
  ASSERT_EQ(RunBinary("simulate", "--out_dir='" + b + "' --overwrite --seed=12").exit_status, 0);
  EXPECT_NE(testing::ReadText(a + "/ensayo.mat"), testing::ReadText(b + "/ensayo.mat"));
}

TEST(SimulateBinary, WritesTheCsvLayoutThatTheEstimatorsRead) {
  ScratchDir scratch;
  const std::string dir = scratch.File("csv");
  const CommandResult result =
      RunBinary("simulate", "--out_dir='" + dir + "' --format=csv --set=tilt_samples=400");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  for (const char* file :
       {"calibration.csv", "trajectory.csv", "landmarks.csv", "scenario.json", "truth.json"}) {
    EXPECT_TRUE(testing::PathExists(dir + "/" + file)) << file;
  }
  const CommandResult trajectory = RunBinary("trajectory", "--data_dir='" + dir + "'");
  EXPECT_EQ(trajectory.exit_status, 0) << trajectory.stderr_text;
  EXPECT_NE(trajectory.stdout_text.find("verdict:"), std::string::npos);
}

void ExpectRefused(const std::string& binary, const std::string& arguments,
                   const std::string& fragment) {
  testing::ExpectBadInputContract(RunBinary(binary, arguments), binary, fragment);
}

TEST(SimulateBinary, RefusesBadInputAndLeavesNothingBehind) {
  ScratchDir scratch;
  const std::string out = scratch.File("out");
  ExpectRefused("simulate", "", "--out_dir is required");
  ExpectRefused("simulate", "--out_dir='" + out + "' --format=xlsx", "--format must be mat or csv");
  ExpectRefused("simulate", "--out_dir='" + out + "' --set=angle_ofset=0.1",
                "--set: 'angle_ofset' is neither a parameter");
  ExpectRefused("simulate",
                "--out_dir='" + out + "' --scenario='" + scratch.File("none.json") + "'",
                "none.json: no such file; check the path");
  scratch.Write("bad.json", "{\"run\": {}}");
  ExpectRefused("simulate", "--out_dir='" + out + "' --scenario='" + scratch.File("bad.json") + "'",
                "bad.json: run.profile is missing");
  // A landmark name that is not a MATLAB identifier cannot go into puntos.mat.
  scratch.Write(
      "names.json",
      R"({"run": {"dt": 0.01, "duration": 1, "profile": {"segments": [{"duration": 1, "acceleration": [0, 0]}]}},
                    "landmarks": {"listed": [{"name": "gate 1", "position": [0, 0]}]}})");
  ExpectRefused("simulate",
                "--out_dir='" + out + "' --scenario='" + scratch.File("names.json") + "'",
                "landmark 'gate 1' cannot be a MATLAB variable name");
  EXPECT_EQ(RunCommand("ls -A '" + scratch.path() + "' | grep -c tmp").stdout_text, "0\n")
      << "temporary folder left";
  EXPECT_FALSE(testing::PathExists(out));
  ASSERT_EQ(RunBinary("simulate", "--out_dir='" + out + "' --set=tilt_samples=100").exit_status, 0);
  ExpectRefused("simulate", "--out_dir='" + out + "'", "exists and is not empty; pass --overwrite");
}

TEST(CoverageBinary, PrintsTheTableAndTheEffectRowsAndWritesJson) {
  ScratchDir scratch;
  const CommandResult result =
      RunBinary("coverage", "--trials=40 --effect_trials=10 --set=tilt_samples=500 --json='" +
                                scratch.File("c.json") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("endpoint ellipse (parameters + run noise)"),
            std::string::npos);
  EXPECT_NE(result.stdout_text.find("scale_nonlinearity_y"), std::string::npos);
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(scratch.File("c.json")));
  EXPECT_EQ(json["trials"].get<int>(), 40);
  EXPECT_EQ(json["effects"].size(), 10u);
  EXPECT_EQ(json["effects"][0]["name"], "angle_offset");
  ExpectRefused("coverage", "--trials=5", "--trials='5' is not a valid int32 in [10, 10000000]");
}

}  // namespace
}  // namespace accelcal
