// The discover binary: the verdict first on the course data, a hidden effect named in
// the JSON with the fields, and its bad-input contract.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::RunBinary;
using testing::ScratchDir;

TEST(DiscoverBinary, PrintsTheVerdictFirstOnTheCourseData) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir out;
  const CommandResult result =
      RunBinary("discover", "--data_dir='" + dir + "' --json='" + out.File("d.json") +
                                "' --bins_csv='" + out.File("bins.csv") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_EQ(result.stdout_text.find(
                "accelcal discover: does the baseline explain the data?\n\n  verdict: the baseline "
                "explains the data"),
            0u)
      << result.stdout_text;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("d.json")));
  EXPECT_TRUE(json["effects"].empty());
  EXPECT_EQ(json["landmark"], "C");
  EXPECT_EQ(json["candidates"].size(), 8u);
  EXPECT_TRUE(json["baseline"]["parameters"].contains("bias_x"));
  EXPECT_TRUE(json["extended"].contains("endpoint"));
  EXPECT_TRUE(json["gain"].contains("cross_validation"));
  EXPECT_EQ(testing::CountLines(testing::ReadText(out.File("bins.csv"))), 1 + 36);
}

TEST(DiscoverBinary, NamesAHiddenEffectInTheJson) {
  ScratchDir out;
  const CommandResult result =
      RunBinary("discover", "--set=bias_drift_y=0.16 --seed=4 --json='" + out.File("d.json") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("verdict: missing: bias_drift_y = "), std::string::npos)
      << result.stdout_text;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("d.json")));
  ASSERT_EQ(json["effects"].size(), 1u);
  const nlohmann::json& effect = json["effects"][0];
  EXPECT_EQ(effect["name"], "bias_drift_y");
  for (const char* key : {"estimate", "stddev", "p_value", "delta_chi2"})
    EXPECT_TRUE(effect[key].is_number()) << key;
  EXPECT_LT(std::abs(effect["estimate"].get<double>() - 0.16), 3 * effect["stddev"].get<double>());
  EXPECT_GT(json["gain"]["cross_validation"]["baseline"].get<double>(),
            json["gain"]["cross_validation"]["extended"].get<double>());
}

TEST(DiscoverBinary, RefusesBadFlags) {
  testing::ExpectBadInputContract(RunBinary("discover", "--alpha=0.7"), "discover",
                                  "--alpha='0.7' is not a valid double in (0, 0.5)");
  testing::ExpectBadInputContract(RunBinary("discover", "--folds=1"), "discover",
                                  "--folds must be 0 (none) or 2 to 100");
  testing::ExpectBadInputContract(RunBinary("discover", "--set=wobble=1"), "discover",
                                  "--set: 'wobble' is neither");
}

}  // namespace
}  // namespace accelcal
