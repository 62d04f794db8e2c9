// calibrate and apply from the outside, on the course data: the calibration file holds what
// an independent fit of the tilt test gives, trajectory with it gives what trajectory with the
// tilt test gives, apply corrects every sample, and what cannot be trusted is refused in one
// line with nothing written (issue 18).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "io/course_data.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::RunBinary;
using testing::ScratchDir;

// calibrate on the course data into `scratch`: the calibration file, or "" if it failed.
std::string CalibrateCourseData(const std::string& dir, const ScratchDir& scratch) {
  const std::string cal = scratch.File("cal.json");
  const CommandResult result =
      RunBinary("calibrate", "--data_dir='" + dir + "' --calibration_out='" + cal + "'");
  EXPECT_EQ(result.exit_status, 0) << result.stderr_text;
  return result.exit_status == 0 ? cal : "";
}

nlohmann::json ReadJson(const std::string& path) {
  return nlohmann::json::parse(testing::ReadText(path), nullptr, false);
}

TEST(CalibrateBinary, HoldsWhatAnIndependentFitOfTheCourseTiltTestGives) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir scratch;
  const std::string out = scratch.File("cal.json");
  const CommandResult result =
      RunBinary("calibrate", "--data_dir='" + dir + "' --calibration_out='" + out + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_EQ(result.stdout_text.rfind("data: " + dir + " (2 files)\n", 0), 0u);
  const nlohmann::json cal = ReadJson(out);
  CalibrationTest test;
  ASSERT_TRUE(LoadCalibrationTest(dir + "/ensayo.mat", &test).ok());
  const char* names[2][2] = {{"bias_x", "scale_x"}, {"bias_y", "scale_y"}};
  const double variances[2] = {0.25, 0.64};  // datos.txt
  for (int axis = 0; axis < 2; ++axis) {
    const testing::PlainAxisFit fit = testing::PlainBaselineFit(test, axis, variances[axis]);
    EXPECT_NEAR(cal["parameters"][names[axis][0]], fit.bias, 1e-12);
    EXPECT_NEAR(cal["parameters"][names[axis][1]], fit.scale, 1e-12);
    const int b = 2 * axis;
    EXPECT_NEAR(cal["covariance"][b][b].get<double>() / fit.var_bias, 1.0, 1e-9);
    EXPECT_NEAR(cal["covariance"][b + 1][b + 1].get<double>() / fit.var_scale, 1.0, 1e-9);
    EXPECT_NEAR(cal["covariance"][b][b + 1].get<double>(), fit.cov_bias_scale,
                1e-9 * std::sqrt(fit.var_bias * fit.var_scale));
    EXPECT_NEAR(cal["fit"]["chi2"][axis == 0 ? "x" : "y"].get<double>() / fit.chi2, 1.0, 1e-9);
  }
  EXPECT_EQ(cal["noise_variance"]["from"], dir + "/datos.txt");
  EXPECT_NE(cal["fit"]["verdict"].get<std::string>().find("the stated noise explains"),
            std::string::npos);
}

TEST(CalibrateBinary, WithoutStatedNoiseEstimatesItFromTheResidualsAndSaysSo) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir scratch;
  const std::string out = scratch.File("cal.json");
  // The tilt test by itself, with no conditions file beside it.
  const CommandResult result = RunBinary(
      "calibrate", "--calibration_file='" + dir + "/ensayo.mat' --calibration_out='" + out + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const nlohmann::json cal = ReadJson(out);
  CalibrationTest test;
  ASSERT_TRUE(LoadCalibrationTest(dir + "/ensayo.mat", &test).ok());
  for (int axis = 0; axis < 2; ++axis) {
    const testing::PlainAxisFit unit = testing::PlainBaselineFit(test, axis, 1.0);
    const double estimated = unit.chi2 / (test.size() - 2);
    EXPECT_NEAR(cal["noise_variance"][axis == 0 ? "x" : "y"].get<double>() / estimated, 1.0, 1e-9);
    const testing::PlainAxisFit fit = testing::PlainBaselineFit(test, axis, estimated);
    EXPECT_NEAR(cal["covariance"][2 * axis][2 * axis].get<double>() / fit.var_bias, 1.0, 1e-9);
  }
  EXPECT_EQ(cal["noise_variance"]["from"], "estimated from the residuals");
  EXPECT_NE(result.stdout_text.find("estimated from the residuals"), std::string::npos);
}

TEST(TrajectoryBinary, ACalibrationFileGivesWhatTheTiltTestItCameFromGives) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir scratch;
  const std::string cal = CalibrateCourseData(dir, scratch);
  ASSERT_FALSE(cal.empty());
  const CommandResult from_test =
      RunBinary("trajectory", "--data_dir='" + dir + "' --json='" + scratch.File("a.json") + "'");
  const CommandResult from_file =
      RunBinary("trajectory", "--data_dir='" + dir + "' --calibration='" + cal + "' --json='" +
                                  scratch.File("b.json") + "'");
  ASSERT_EQ(from_file.exit_status, 0) << from_file.stderr_text;
  const nlohmann::json a = ReadJson(scratch.File("a.json"));
  const nlohmann::json b = ReadJson(scratch.File("b.json"));
  EXPECT_EQ(a["endpoint"], b["endpoint"]);
  EXPECT_EQ(a["endpoint_covariance"], b["endpoint_covariance"]);
  EXPECT_EQ(a["reached"], b["reached"]);
  EXPECT_EQ(b["input_files"]["calibration"]["path"], cal);
  EXPECT_NE(from_file.stdout_text.find("calibration  " + cal), std::string::npos);
}

TEST(ApplyBinary, CorrectsEverySampleOfTheCourseRun) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir scratch;
  const std::string cal = CalibrateCourseData(dir, scratch);
  ASSERT_FALSE(cal.empty());
  const std::string out = scratch.File("corrected.csv");
  const CommandResult result = RunBinary(
      "apply", "--calibration='" + cal + "' --in='" + dir + "/acel.mat' --out='" + out + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const nlohmann::json calibration = ReadJson(cal);
  VehicleRun run;
  ASSERT_TRUE(LoadVehicleRun(dir + "/acel.mat", &run).ok());
  std::istringstream lines(testing::ReadText(out));
  std::string line;
  int row = -1;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (row++ < 0) {
      EXPECT_EQ(line, "t_s,ax_mps2,ay_mps2,sigma_ax_mps2,sigma_ay_mps2,corr_axy");
      continue;
    }
    double t, ax, ay;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &t, &ax, &ay), 3) << line;
    const nlohmann::json& p = calibration["parameters"];
    EXPECT_EQ(t, run.timestamp_s[row - 1]);
    EXPECT_NEAR(
        ax,
        (run.measured_x[row - 1] - p["bias_x"].get<double>()) / (1 + p["scale_x"].get<double>()),
        1e-13);
    EXPECT_NEAR(
        ay,
        (run.measured_y[row - 1] - p["bias_y"].get<double>()) / (1 + p["scale_y"].get<double>()),
        1e-13);
  }
  EXPECT_EQ(row, run.size());
}

// A log to correct need not be uniformly sampled (a dropped sample is common); only a run to
// integrate must be.
TEST(ApplyBinary, CorrectsALogWithADroppedSample) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir scratch;
  const std::string cal = CalibrateCourseData(dir, scratch);
  ASSERT_FALSE(cal.empty());
  const std::string log =
      scratch.Write("log.csv", "t,ax,ay\n0,1,2\n0.01,1,2\n0.03,1,2\n0.04,1,2\n");
  const CommandResult result = RunBinary("apply", "--calibration='" + cal + "' --in='" + log +
                                                      "' --out='" + scratch.File("o.csv") + "'");
  EXPECT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(testing::ReadText(scratch.File("o.csv")).find("\n0.03,"), std::string::npos);
  const CommandResult trajectory =
      RunBinary("trajectory", "--data_dir='" + dir + "' --run_file='" + log + "'");
  EXPECT_NE(trajectory.stderr_text.find("not uniformly spaced"), std::string::npos)
      << trajectory.stderr_text;
}

// Each refusal: exit status 2, one line naming the problem, nothing written.
TEST(CalibrateAndApply, RefuseWhatTheyCannotTrustAndWriteNothing) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir scratch;
  const std::string cal = CalibrateCourseData(dir, scratch);
  ASSERT_FALSE(cal.empty());
  nlohmann::json wrong_unit = ReadJson(cal);
  wrong_unit["units"]["bias_x"] = "mg";
  const std::string mg = scratch.Write("mg.json", wrong_unit.dump());
  const std::string backwards =
      scratch.Write("backwards.csv", "t,ax,ay\n0,1,2\n0.01,1,2\n0.005,1,2\n");
  const std::string out = scratch.File("out");
  struct Case {
    const char* binary;
    std::string flags;
    const char* expected;
  };
  const Case cases[] = {
      {"calibrate", "--calibration_out='" + out + "'", "give the tilt test"},
      {"calibrate", "--data_dir='" + dir + "'", "--calibration_out must name"},
      {"calibrate",
       "--data_dir='" + dir + "' --noise_variance=0.25 --calibration_out='" + out + "'",
       "--noise_variance must be two numbers"},
      {"calibrate",
       "--data_dir='" + dir + "' --noise_variance=0.25,0.64, --calibration_out='" + out + "'",
       "--noise_variance must be two numbers"},
      {"calibrate",
       "--data_dir='" + dir + "' --noise_variance=0.25,-1 --calibration_out='" + out + "'",
       "--noise_variance"},
      {"calibrate", "--data_dir='" + dir + "' --calibration_out='" + dir + "/datos.txt'",
       "datos.txt"},
      {"apply", "--calibration='" + mg + "' --in='" + dir + "/acel.mat' --out='" + out + "'",
       "units/bias_x must be \"m/s^2\""},
      {"apply",
       "--calibration='" + dir + "/datos.txt' --in='" + dir + "/acel.mat' --out='" + out + "'",
       "not valid JSON"},
      {"apply", "--calibration='" + cal + "' --in='" + backwards + "' --out='" + out + "'",
       "t is not strictly increasing: t(3) = 0.005 s after 0.01 s"},
      {"apply", "--calibration='" + cal + "' --in='" + dir + "/acel.mat'", "--out must name"},
      {"apply", "--calibration='" + cal + "' --in='" + dir + "/acel.mat' --out='" + cal + "'",
       "--out"},
      {"trajectory", "--data_dir='" + dir + "' --calibration='" + mg + "'", "units/bias_x"},
      {"trajectory",
       "--data_dir='" + dir + "' --calibration='" + cal + "' --calibration_file='" + dir +
           "/ensayo.mat'",
       "drop one of the two"},
  };
  const std::string cal_before = testing::ReadText(cal);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.flags);
    testing::ExpectBadInputContract(RunBinary(c.binary, c.flags), c.binary, c.expected);
    EXPECT_FALSE(testing::PathExists(out));
  }
  EXPECT_EQ(testing::ReadText(cal), cal_before);
}

}  // namespace
}  // namespace accelcal
