// The discover binary: the verdict first on the course data, a hidden effect named in
// the JSON with the fields, structure outside the catalogue not passed off as
// explained, and its bad-input contract.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::RunBinary;
using testing::ScratchDir;

const std::set<std::string> kVerdictCodes = {"explained", "missing", "unexplained",
                                             "cannot_tell_apart"};

TEST(DiscoverBinary, PrintsTheVerdictFirstOnTheCourseData) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir out;
  const CommandResult result =
      RunBinary("discover", "--data_dir='" + dir + "' --json='" + out.File("d.json") +
                                "' --bins_csv='" + out.File("bins.csv") + "' --residuals_csv='" +
                                out.File("residuals.csv") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  // The data line first (io/provenance.h), then the verdict.
  EXPECT_EQ(result.stdout_text.find("data: " + dir +
                                    " (4 files)\n"
                                    "accelcal discover: does the baseline explain the data?\n\n"
                                    "  verdict: the baseline explains the data"),
            0u)
      << result.stdout_text;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("d.json")));
  EXPECT_TRUE(json["effects"].empty());
  EXPECT_EQ(json["reached"], "C");
  EXPECT_EQ(json["candidates"].size(), 8u);
  EXPECT_TRUE(json["baseline"]["parameters"].contains("bias_x"));
  EXPECT_TRUE(json["extended"].contains("endpoint"));
  EXPECT_TRUE(json["gain"].contains("cross_validation"));
  EXPECT_EQ(testing::CountLines(testing::ReadText(out.File("bins.csv"))), 1 + 36);
  // The four-verdict form and what backs it.
  ASSERT_TRUE(json["verdict_code"].is_string());
  EXPECT_EQ(kVerdictCodes.count(json["verdict_code"].get<std::string>()), 1u)
      << json["verdict_code"];
  EXPECT_EQ(json["verdict_code"], "explained");
  EXPECT_NE(result.stdout_text.find("  in short: explained"), std::string::npos);
  ASSERT_TRUE(json["checks"].is_array());
  EXPECT_FALSE(json["checks"].empty());
  for (const nlohmann::json& check : json["checks"]) {
    for (const char* key : {"name", "description"}) EXPECT_TRUE(check[key].is_string()) << key;
    for (const char* key : {"statistic", "dof", "p_value"})
      EXPECT_TRUE(check[key].is_number() || check[key].is_null()) << key;
    EXPECT_TRUE(check["flagged"].is_boolean());
  }
  EXPECT_TRUE(json["remaining"].is_array());
  EXPECT_TRUE(json["remaining"].empty());
  EXPECT_TRUE(json["ambiguities"].is_array());
  EXPECT_TRUE(json["robust_fit"].is_boolean());
  for (const char* axis : {"x", "y"}) {
    EXPECT_TRUE(json["noise"][axis]["ratio"].is_number()) << axis;  // the older figures stay
    EXPECT_TRUE(json["noise"][axis]["analysis"]["variance_ratio"].is_number()) << axis;
    EXPECT_TRUE(json["noise"][axis]["model"]["outliers"].is_array()) << axis;
    EXPECT_TRUE(json["noise"][axis]["findings"].empty()) << axis;
  }
  for (const char* key : {"null_mean", "null_stddev", "z"})
    EXPECT_TRUE(json["gain"]["cross_validation"][key].is_number()) << key;
  // The final residual per sample, decimated to 5000 rows for the 20001-sample test.
  const std::string residuals = testing::ReadText(out.File("residuals.csv"));
  EXPECT_EQ(residuals.rfind("sample,theta_rad,residual_x,residual_y,outlier_x,outlier_y\n", 0), 0u);
  EXPECT_EQ(testing::CountLines(residuals), 1 + 5000);
  EXPECT_EQ(result.stdout_text.find("nan"), std::string::npos);
}

// Structure outside the catalogue (a theta harmonic; time-correlated noise) is not called
// "explained": it is named as what remains, or as a noise finding.
TEST(DiscoverBinary, DoesNotCallStructureOutsideTheCatalogueExplained) {
  for (const char* disturbance :
       {"theta_harmonic_order=2,theta_harmonic_x=0.05", "noise_ar1_x=0.6"}) {
    SCOPED_TRACE(disturbance);
    ScratchDir out;
    const CommandResult result =
        RunBinary("discover", std::string("--set=") + disturbance + " --seed=1 --json='" +
                                  out.File("d.json") + "'");
    ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
    const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("d.json")));
    ASSERT_TRUE(json["verdict_code"].is_string());
    EXPECT_EQ(kVerdictCodes.count(json["verdict_code"].get<std::string>()), 1u);
    EXPECT_NE(json["verdict_code"], "explained") << result.stdout_text;
    size_t findings = 0;
    for (const char* axis : {"x", "y"}) findings += json["noise"][axis]["findings"].size();
    EXPECT_TRUE(!json["remaining"].empty() || findings > 0) << result.stdout_text;
    EXPECT_EQ(result.stdout_text.find("verdict: the baseline explains"), std::string::npos);
    EXPECT_EQ(result.stdout_text.find("nan"), std::string::npos);
  }
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
