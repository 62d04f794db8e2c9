// calibrate_imu end to end: imu_tk's printed output reproduced by the binary on imu_tk's own
// log (issue 20's "done when"), its JSON, and the bad-input contract.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "test_support.h"

namespace accelcal {
namespace {

using testing::ExpectBadInputContract;
using testing::RunBinary;

constexpr char kXsensFlags[] = "--g=9.81744 --mode=imu_tk --init_rest_s=50 --initial_bias=32768";

TEST(CalibrateImuCli, PrintsImuTksCostForEveryKAndItsParametersAtK6) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  const std::string json_path = scratch.File("out.json");
  const testing::CommandResult result = RunBinary(
      "calibrate_imu", "--log='" + dir + "/xsens_acc.mat' " + kXsensFlags + " --json=" + json_path);
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::string& out = result.stdout_text;
  EXPECT_EQ(out.rfind("data: " + dir + "/xsens_acc.mat\n", 0), 0u) << out;
  // Each row: k, threshold, detected, used, our cost, iterations, imu_tk's cost and count.
  const char* rows[] = {"0.134724", "0.131345", "0.126126", "0.120558", "0.120131",
                        "0.120586", "0.121338", "0.121422", "0.13824"};
  for (const char* cost : rows) {
    // Ours and imu_tk's side by side: the cost appears twice on its row.
    const size_t first = out.find(std::string(" ") + cost + " ");
    ASSERT_NE(first, std::string::npos) << cost << "\n" << out;
    const size_t line_end = out.find('\n', first);
    EXPECT_NE(out.substr(first + 1, line_end - first - 1).find(cost, 1), std::string::npos)
        << out.substr(first, line_end - first);
  }
  EXPECT_NE(out.find("Chosen: k = 6, the lowest final cost 0.120131"), std::string::npos) << out;
  EXPECT_NE(out.find("1/414.459        1/414.459"), std::string::npos) << out;
  EXPECT_NE(out.find("33124.183        33124.2"), std::string::npos) << out;

  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  EXPECT_EQ(json["mode"], "imu_tk");
  EXPECT_EQ(json["chosen_k"], 6);
  ASSERT_EQ(json["threshold_sweep"].size(), 9u);
  EXPECT_EQ(json["threshold_sweep"][0]["k"], 2);
  EXPECT_EQ(json["threshold_sweep"][0]["intervals"], 42);
  EXPECT_NEAR(json["cost"].get<double>(), 0.120131, 5e-7);
  EXPECT_EQ(json["intervals"].size(), 38u);
  EXPECT_TRUE(json["intervals"][0].contains("mean"));
  EXPECT_TRUE(json["intervals"][0].contains("noise"));
  EXPECT_NEAR(json["parameters"]["bias_x"].get<double>(), 33124.2, 0.05);
  EXPECT_EQ(json["units"]["misalignment_yz"], "rad");
  EXPECT_EQ(json["input_files"]["log"]["sha256"],
            "335a234736ff4dd8741118283d5d4cd389ac54b04d00e6cd8d48ca3e532b7510");
  EXPECT_TRUE(json.contains("command_line"));
}

// Mode ml on the same log: every parameter +- sigma, the fit statistic, and imu_tk's result
// beside it. The white-noise model does not explain the xsens pose means (chi2/dof ~ 15, the
// README), so the ML parameters are compared with imu_tk's within a loose 20 sigma: the
// differences are reported, not hidden.
TEST(CalibrateImuCli, ModeMlPrintsEveryParameterWithSigmaAndTheFitStatistic) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  const std::string json_path = scratch.File("ml.json");
  const testing::CommandResult result =
      RunBinary("calibrate_imu", "--log='" + dir + "/xsens_acc.mat' --g=9.81744 --mode=ml " +
                                     "--init_rest_s=50 --initial_bias=32768 --json=" + json_path);
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::string& out = result.stdout_text;
  EXPECT_NE(out.find("mode ml"), std::string::npos) << out;
  EXPECT_NE(out.find("on 29 degrees of freedom, chi2/dof = "), std::string::npos) << out;
  EXPECT_NE(out.find("does NOT explain the residuals"), std::string::npos) << out;

  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  EXPECT_EQ(json["mode"], "ml");
  for (const char* key : {"parameters", "stddev", "units", "covariance", "chi2", "dof",
                          "chi2_per_dof", "p_value", "intervals", "imu_tk"})
    EXPECT_TRUE(json.contains(key)) << key;
  EXPECT_EQ(json["dof"], 29);
  EXPECT_EQ(json["intervals"].size(), 38u);
  EXPECT_EQ(json["covariance"]["parameter_order"].size(), 9u);
  EXPECT_EQ(json["covariance"]["parameter_order"][0], "misalignment_yz");
  const double chi2_per_dof = json["chi2_per_dof"].get<double>();
  EXPECT_GT(chi2_per_dof, 5.0);  // issue 21: ~16
  EXPECT_LT(json["p_value"].get<double>(), 1e-6);
  for (const auto& item : json["parameters"].items()) {
    const std::string& name = item.key();
    const double sigma = json["stddev"][name].get<double>();
    EXPECT_GT(sigma, 0.0) << name;
    EXPECT_TRUE(std::isfinite(sigma)) << name;
    const double difference =
        item.value().get<double>() - json["imu_tk"]["parameters"][name].get<double>();
    EXPECT_LT(std::abs(difference), 20.0 * sigma) << name;
    EXPECT_NE(out.find(name), std::string::npos) << name;
  }
  EXPECT_EQ(json["units"]["bias_x"], "count");
}

TEST(CalibrateImuCli, RefusesABadLogInOneLineAndWritesNothing) {
  testing::ScratchDir scratch;
  const std::string log = scratch.Write("log.txt", "0.00 1 2 3\n0.01 1 nan 3\n");
  const std::string json = scratch.File("o.json");
  const testing::CommandResult result =
      RunBinary("calibrate_imu", "--log=" + log + " --json=" + json);
  ExpectBadInputContract(result, "calibrate_imu", log + ": line 2, column 3 (y)");
  EXPECT_FALSE(testing::PathExists(json));
}

TEST(CalibrateImuCli, RefusesALogTooShortForTheDetector) {
  testing::ScratchDir scratch;
  std::string text;
  for (int i = 0; i < 50; ++i) text += std::to_string(0.01 * (i + 1)) + " 1 2 3\n";
  const std::string log = scratch.Write("log.txt", text);
  const testing::CommandResult result = RunBinary("calibrate_imu", "--log=" + log);
  ExpectBadInputContract(result, "calibrate_imu", "record a longer session");
}

TEST(CalibrateImuCli, RefusesAMissingLogFlag) {
  const testing::CommandResult result = RunBinary("calibrate_imu", "");
  ExpectBadInputContract(result, "calibrate_imu", "--log is required");
}

}  // namespace
}  // namespace accelcal
