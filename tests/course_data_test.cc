// The course's measured data, read as is, and the reference report's figures reproduced
// from it (../shared/reference/seed-report.md, Table 1 and equation (4)).

#include "io/course_data.h"

#include <gtest/gtest.h>

#include <cmath>

#include "estimation/ceres_linear_ls.h"
#include "estimation/error_budget.h"
#include "estimation/landmark_decision.h"
#include "estimation/linear_ls.h"
#include "estimation/trajectory.h"
#include "io/course_csv.h"
#include "io/run_conditions.h"
#include "models/tilt_table.h"
#include "test_support.h"

namespace accelcal {
namespace {

constexpr double kTwoPi = 6.283185307179586;

struct CourseFit {
  CalibrationTest test;
  RunConditions conditions;
  BaselineFit fit;
};

CourseFit FitCourseData(const std::string& dir) {
  CourseFit result;
  DataFiles files;
  EXPECT_TRUE(ResolveDataFiles(dir, &files).ok());
  EXPECT_TRUE(LoadCalibrationTest(files.calibration, &result.test).ok());
  EXPECT_TRUE(LoadRunConditions(files.conditions, &result.conditions).ok());
  LinearLsOptions options;
  options.noise_variance_x = result.conditions.noise_variance_x;
  options.noise_variance_y = result.conditions.noise_variance_y;
  const Status status = EstimateLinearLs(result.test, options, &result.fit);
  EXPECT_TRUE(status.ok()) << status.message();
  return result;
}

// |actual - reported| within one unit of the last digit the report printed.
void ExpectWithinLastDigit(double actual, double reported, double unit, const char* name) {
  EXPECT_LE(std::abs(actual - reported), unit)
      << name << ": " << actual << " vs the report's " << reported;
}

TEST(CourseData, LoadsTheFourFilesAsIs) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  DataFiles files;
  ASSERT_TRUE(ResolveDataFiles(dir, &files).ok());
  EXPECT_EQ(files.layout, DataLayout::kCourseMat);

  CalibrationTest test;
  ASSERT_TRUE(LoadCalibrationTest(files.calibration, &test).ok());
  ASSERT_EQ(test.size(), 20001);
  EXPECT_DOUBLE_EQ(test.theta_rad.front(), 0.0);
  EXPECT_NEAR(test.theta_rad.back(), kTwoPi, 1e-12);
  EXPECT_NEAR(test.measured_x.front(), -0.13007198, 1e-8);   // datos(1,1), as read by scipy
  EXPECT_NEAR(test.measured_y.front(), -10.14776655, 1e-8);  // datos(1,2)

  VehicleRun run;
  const Status run_status = LoadVehicleRun(files.run, &run);
  ASSERT_TRUE(run_status.ok()) << run_status.message();
  ASSERT_EQ(run.size(), 6000);
  EXPECT_NEAR(run.timestamp_s.back(), 59.99, 1e-9);
  EXPECT_NEAR(run.measured_x.front(), 0.04550114, 1e-8);

  std::vector<Landmark> landmarks;
  ASSERT_TRUE(LoadLandmarks(files.landmarks, &landmarks).ok());
  ASSERT_EQ(landmarks.size(), 4u);
  EXPECT_EQ(landmarks[0].name, "A");
  EXPECT_NEAR(landmarks[0].x_m, 353.63651708, 1e-7);
  EXPECT_NEAR(landmarks[0].y_m, 73.24974234, 1e-7);
  EXPECT_EQ(landmarks[2].name, "C");
  EXPECT_NEAR(landmarks[2].x_m, 459.84, 1e-9);
  EXPECT_EQ(landmarks[3].name, "D");

  RunConditions conditions;
  ASSERT_TRUE(LoadRunConditions(files.conditions, &conditions).ok());
  EXPECT_EQ(conditions.initial_position_x_m, 0.0);
  EXPECT_EQ(conditions.initial_velocity_x_mps, 1.0);
  EXPECT_EQ(conditions.initial_velocity_y_mps, 3.0);
  EXPECT_EQ(conditions.noise_variance_x, 0.25);
  EXPECT_EQ(conditions.noise_variance_y, 0.64);
}

TEST(CourseData, ReproducesTheReportsTableOne) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  const BaselineFit fit = FitCourseData(dir).fit;
  ExpectWithinLastDigit(fit.parameters[kBiasX], 7.667e-2, 1e-5, "bias_x");
  ExpectWithinLastDigit(fit.parameters[kScaleX], -3.014e-2, 0.5e-5, "scale_x");
  ExpectWithinLastDigit(fit.parameters[kBiasY], -1.751e-2, 0.5e-5, "bias_y");
  ExpectWithinLastDigit(fit.parameters[kScaleY], 1.004e-2, 0.5e-5, "scale_y");
  // To more digits, against numpy.linalg.lstsq on the same files (an independent
  // solver): the report's 7.667e-2 is a rounding slip for 7.6664e-2, the only one of
  // its four figures off in the last digit.
  EXPECT_NEAR(fit.parameters[kBiasX], 7.666381814121e-02, 1e-12);
  EXPECT_NEAR(fit.parameters[kScaleX], -3.014181300939e-02, 1e-12);
  EXPECT_NEAR(fit.parameters[kBiasY], -1.750807246292e-02, 1e-12);
  EXPECT_NEAR(fit.parameters[kScaleY], 1.004157204455e-02, 1e-12);
}

TEST(CourseData, ReproducesTheReportsCovarianceAndFindsItsTypo) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  const CourseFit course = FitCourseData(dir);
  const Eigen::Matrix4d& covariance = course.fit.covariance;
  ExpectWithinLastDigit(covariance(kScaleX, kScaleX), 2.603e-7, 0.5e-10, "var scale_x");
  ExpectWithinLastDigit(covariance(kBiasY, kBiasY), 3.200e-5, 0.5e-8, "var bias_y");
  ExpectWithinLastDigit(covariance(kScaleY, kScaleY), 6.663e-7, 0.5e-10, "var scale_y");
  // Even the report's off-diagonal terms, which come from sum(sin theta_i) = -7e-9 and
  // sum(cos theta_i) of the sampled angles, are reproduced.
  EXPECT_NEAR(covariance(kBiasX, kScaleX) / -8.915e-19, 1.0, 1e-3);
  EXPECT_NEAR(covariance(kBiasY, kScaleY) / 3.265e-10, 1.0, 1e-3);
  // var(bias_x): for a design with sum(f) ~ 0 it is sigma_x^2 / N = 0.25 / 20001
  // = 1.24994e-5, i.e. 1.250e-5. The report prints 1.245e-5, five units off in its
  // last digit: a transcription error (its other three variances and both covariances
  // match to every printed digit).
  const double sigma2_over_n = 0.25 / 20001.0;
  EXPECT_NEAR(covariance(kBiasX, kBiasX), sigma2_over_n, 1e-12 * sigma2_over_n);
  EXPECT_GT(std::abs(covariance(kBiasX, kBiasX) - 1.245e-5), 4e-8);
}

TEST(CourseData, ChiSquareAgreesWithTheStatedNoise) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  const BaselineFit fit = FitCourseData(dir).fit;
  // Independent figures: sum of squared lstsq residuals / sigma^2 (numpy).
  EXPECT_NEAR(fit.chi2_x.chi2, 19847.931, 1e-3);
  EXPECT_NEAR(fit.chi2_y.chi2, 19964.104, 1e-3);
  EXPECT_EQ(fit.chi2_x.dof, 19999);
  EXPECT_GT(fit.chi2_x.p_value, 0.01);
  EXPECT_GT(fit.chi2_y.p_value, 0.01);
}

TEST(CourseData, BothSolversAgreeOnTheCourseData) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  const CourseFit course = FitCourseData(dir);
  CeresLinearLsOptions options;
  options.model.noise_variance_x = course.conditions.noise_variance_x;
  options.model.noise_variance_y = course.conditions.noise_variance_y;
  CeresLinearLsResult ceres;
  ASSERT_TRUE(EstimateLinearLsWithCeres(course.test, options, &ceres).ok());
  const FitDifference difference = CompareFits(course.fit, ceres.fit);
  EXPECT_LT(difference.parameters, 1e-9);
  EXPECT_LT(difference.covariance, 1e-9);
}

TEST(CourseData, ACsvCopyGivesTheSameAnswer) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  const CourseFit from_mat = FitCourseData(dir);
  testing::ScratchDir scratch;
  ASSERT_TRUE(WriteCalibrationCsv(scratch.File("calibration.csv"), from_mat.test).ok());
  scratch.Write("scenario.json", ScenarioJson(from_mat.conditions));
  DataFiles files;
  ASSERT_TRUE(ResolveDataFiles(scratch.path(), &files).ok());
  EXPECT_EQ(files.layout, DataLayout::kCsv);
  const CourseFit from_csv = FitCourseData(scratch.path());
  // %.17g round-trips doubles exactly, so the answers are identical, not just close.
  EXPECT_EQ(from_csv.fit.parameters, from_mat.fit.parameters);
  EXPECT_EQ(from_csv.fit.covariance, from_mat.fit.covariance);
  EXPECT_EQ(from_csv.fit.chi2_x.chi2, from_mat.fit.chi2_x.chi2);
}

// The vehicle run of the course, dead-reckoned with the baseline fit. The figures are the
// program's; the test recomputes them independently: the endpoint by a plain double
// loop, the noise part by brute-force impulse responses and the closed form
// sigma^2 dt T^3 / 3, the parameter part from the analytic derivatives.
TEST(CourseData, TheVehicleReachedCAndTheNoiseDominatesTheUncertainty) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  const CourseFit course = FitCourseData(dir);
  DataFiles files;
  ASSERT_TRUE(ResolveDataFiles(dir, &files).ok());
  VehicleRun run;
  ASSERT_TRUE(LoadVehicleRun(files.run, &run).ok());
  std::vector<Landmark> landmarks;
  ASSERT_TRUE(LoadLandmarks(files.landmarks, &landmarks).ok());
  DeadReckoningResult result;
  ASSERT_TRUE(DeadReckon(run, course.conditions, course.fit, TrajectoryOptions(), &result).ok());

  // Pinned figures (printed by build/bin/trajectory on the course data).
  EXPECT_NEAR(result.endpoint.x(), 468.685, 1e-3);
  EXPECT_NEAR(result.endpoint.y(), 42.140, 1e-3);
  EXPECT_NEAR(result.raw_endpoint.x(), 594.315, 1e-3);
  EXPECT_NEAR(result.raw_endpoint.y(), 9.252, 1e-3);
  EXPECT_NEAR(result.parameter_part(0, 0), 43.072, 1e-3);
  EXPECT_NEAR(result.parameter_part(1, 1), 101.568, 1e-3);
  EXPECT_NEAR(result.noise_part(0, 0), 191.243, 1e-3);
  EXPECT_NEAR(result.noise_part(1, 1), 451.401, 1e-3);

  // Independent: a plain loop over (m - b)/(1 + s).
  const Eigen::Vector4d& p = course.fit.parameters;
  double px = 0.0, py = 0.0, vx = 1.0, vy = 3.0;
  const double dt = 0.01;
  for (int j = 1; j < run.size(); ++j) {
    const double ax0 = (run.measured_x[j - 1] - p[kBiasX]) / (1 + p[kScaleX]);
    const double ax1 = (run.measured_x[j] - p[kBiasX]) / (1 + p[kScaleX]);
    const double ay0 = (run.measured_y[j - 1] - p[kBiasY]) / (1 + p[kScaleY]);
    const double ay1 = (run.measured_y[j] - p[kBiasY]) / (1 + p[kScaleY]);
    const double vx1 = vx + dt / 2 * (ax0 + ax1);
    const double vy1 = vy + dt / 2 * (ay0 + ay1);
    px += dt / 2 * (vx + vx1);
    py += dt / 2 * (vy + vy1);
    vx = vx1;
    vy = vy1;
  }
  EXPECT_NEAR(result.endpoint.x(), px, 1e-6);
  EXPECT_NEAR(result.endpoint.y(), py, 1e-6);
  // Independent: sigma^2 dt T^3 / 3 / (1 + s)^2, within the discretisation's 0.1%.
  const double t3 = std::pow(59.99, 3);
  EXPECT_NEAR(result.noise_part(0, 0) / (0.25 * dt * t3 / 3 / std::pow(1 + p[kScaleX], 2)), 1.0,
              3e-3);
  EXPECT_NEAR(result.noise_part(1, 1) / (0.64 * dt * t3 / 3 / std::pow(1 + p[kScaleY], 2)), 1.0,
              3e-3);

  const LandmarkDecision decision =
      DecideLandmark(result.endpoint, result.covariance, landmarks, 0.01);
  EXPECT_EQ(decision.reached, "C");
  EXPECT_NEAR(decision.scores[2].mahalanobis2, 0.910, 1e-3);
  EXPECT_GT(decision.scores[2].posterior, 0.999999);
  EXPECT_NEAR(decision.scores[2].p_value, 0.634, 1e-3);
  // Without the run's own noise (the other group bounded only the parameter terms), the
  // ellipse is 2.3 times too small per axis: C's squared distance grows from 0.91 to 4.95
  // (p = 0.084). C still passes here, but a 95% ellipse drawn that way covers the truth
  // far less than 95% of the time (see trajectory_test's Monte Carlo).
  const LandmarkDecision parameters_only =
      DecideLandmark(result.endpoint, result.parameter_part, landmarks, 0.01);
  EXPECT_NEAR(parameters_only.scores[2].mahalanobis2, 4.95, 0.01);
  EXPECT_NEAR(std::sqrt(result.covariance(0, 0) / result.parameter_part(0, 0)), 2.33, 0.01);

  const auto budget = ComputeErrorBudget(result, course.fit, run, course.conditions);
  EXPECT_STREQ(budget[0].dominant, "noise");
  EXPECT_STREQ(budget[1].dominant, "noise");
  EXPECT_NEAR(budget[0].noise.three_sigma_m / budget[0].noise.report_m, 27.7, 0.05);
  EXPECT_NEAR(budget[1].noise.three_sigma_m / budget[1].noise.report_m, 26.6, 0.05);
}

}  // namespace
}  // namespace accelcal
