// The course's measured data, read as is, and the reference report's figures reproduced
// from it (../shared/reference/seed-report.md, Table 1 and equation (4)).

#include "io/course_data.h"

#include <gtest/gtest.h>

#include <cmath>

#include "estimation/tilt_table/ceres_linear_ls.h"
#include "estimation/tilt_table/error_budget.h"
#include "estimation/tilt_table/landmark_decision.h"
#include "estimation/tilt_table/linear_ls.h"
#include "estimation/tilt_table/trajectory.h"
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
  LinearLsOptions options = LinearLsOptionsFor(result.conditions, kCourseGravityMps2);
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
  ExpectWithinLastDigit(fit.Value(Parameter::kBiasX), 7.667e-2, 1e-5, "bias_x");
  ExpectWithinLastDigit(fit.Value(Parameter::kScaleX), -3.014e-2, 0.5e-5, "scale_x");
  ExpectWithinLastDigit(fit.Value(Parameter::kBiasY), -1.751e-2, 0.5e-5, "bias_y");
  ExpectWithinLastDigit(fit.Value(Parameter::kScaleY), 1.004e-2, 0.5e-5, "scale_y");
  // To more digits, against numpy.linalg.lstsq on the same files (an independent
  // solver): the report's 7.667e-2 is a rounding slip for 7.6664e-2, the only one of
  // its four figures off in the last digit.
  EXPECT_NEAR(fit.Value(Parameter::kBiasX), 7.666381814121e-02, 1e-12);
  EXPECT_NEAR(fit.Value(Parameter::kScaleX), -3.014181300939e-02, 1e-12);
  EXPECT_NEAR(fit.Value(Parameter::kBiasY), -1.750807246292e-02, 1e-12);
  EXPECT_NEAR(fit.Value(Parameter::kScaleY), 1.004157204455e-02, 1e-12);
  // And against the normal equations solved here.
  const CourseFit course = FitCourseData(dir);
  const testing::PlainAxisFit x = testing::PlainBaselineFit(course.test, 0, 0.25);
  const testing::PlainAxisFit y = testing::PlainBaselineFit(course.test, 1, 0.64);
  EXPECT_NEAR(fit.Value(Parameter::kBiasX), x.bias, 1e-12);
  EXPECT_NEAR(fit.Value(Parameter::kScaleX), x.scale, 1e-12);
  EXPECT_NEAR(fit.Value(Parameter::kBiasY), y.bias, 1e-12);
  EXPECT_NEAR(fit.Value(Parameter::kScaleY), y.scale, 1e-12);
}

TEST(CourseData, ReproducesTheReportsCovarianceAndFindsItsTypo) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  const CourseFit course = FitCourseData(dir);
  ExpectWithinLastDigit(course.fit.Covariance(Parameter::kScaleX, Parameter::kScaleX), 2.603e-7,
                        0.5e-10, "var scale_x");
  ExpectWithinLastDigit(course.fit.Covariance(Parameter::kBiasY, Parameter::kBiasY), 3.200e-5,
                        0.5e-8, "var bias_y");
  ExpectWithinLastDigit(course.fit.Covariance(Parameter::kScaleY, Parameter::kScaleY), 6.663e-7,
                        0.5e-10, "var scale_y");
  // Even the report's off-diagonal terms, which come from sum(sin theta_i) = -7e-9 and
  // sum(cos theta_i) of the sampled angles, are reproduced.
  EXPECT_NEAR(course.fit.Covariance(Parameter::kBiasX, Parameter::kScaleX) / -8.915e-19, 1.0, 1e-3);
  EXPECT_NEAR(course.fit.Covariance(Parameter::kBiasY, Parameter::kScaleY) / 3.265e-10, 1.0, 1e-3);
  // var(bias_x): for a design with sum(f) ~ 0 it is sigma_x^2 / N = 0.25 / 20001
  // = 1.24994e-5, i.e. 1.250e-5. The report prints 1.245e-5, five units off in its
  // last digit: a transcription error (its other three variances and both covariances
  // match to every printed digit).
  const double sigma2_over_n = 0.25 / 20001.0;
  EXPECT_NEAR(course.fit.Covariance(Parameter::kBiasX, Parameter::kBiasX), sigma2_over_n,
              1e-12 * sigma2_over_n);
  EXPECT_GT(std::abs(course.fit.Covariance(Parameter::kBiasX, Parameter::kBiasX) - 1.245e-5), 4e-8);
}

TEST(CourseData, ChiSquareAgreesWithTheStatedNoise) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  const BaselineFit fit = FitCourseData(dir).fit;
  // Independent figures: sum of squared lstsq residuals / sigma^2 (numpy).
  EXPECT_NEAR(fit.chi2_x.chi2, 19847.931, 1e-3);
  EXPECT_NEAR(fit.chi2_y.chi2, 19964.104, 1e-3);
  const CourseFit course = FitCourseData(dir);
  const double plain_x = testing::PlainBaselineFit(course.test, 0, 0.25).chi2;
  const double plain_y = testing::PlainBaselineFit(course.test, 1, 0.64).chi2;
  EXPECT_NEAR(fit.chi2_x.chi2, plain_x, 1e-6 * plain_x);
  EXPECT_NEAR(fit.chi2_y.chi2, plain_y, 1e-6 * plain_y);
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
// program's (pinned as the README prints them); the test recomputes each independently: the
// endpoints by a plain double loop, the noise part by brute-force impulse responses and the
// closed form sigma^2 dt T^3 / 3, the parameter part from the analytic derivatives of the
// corrected accelerations, C's Mahalanobis distance and p-value from those.
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

  // The figures build/bin/trajectory prints (README), each recomputed independently below.
  EXPECT_NEAR(result.endpoint.x(), 468.685, 1e-3);
  EXPECT_NEAR(result.endpoint.y(), 42.140, 1e-3);
  EXPECT_NEAR(result.raw_endpoint.x(), 594.315, 1e-3);
  EXPECT_NEAR(result.raw_endpoint.y(), 9.252, 1e-3);
  EXPECT_NEAR(result.parameter_part(0, 0), 43.072, 1e-3);
  EXPECT_NEAR(result.parameter_part(1, 1), 101.568, 1e-3);
  EXPECT_NEAR(result.noise_part(0, 0), 191.243, 1e-3);
  EXPECT_NEAR(result.noise_part(1, 1), 451.401, 1e-3);

  // Independent: the spec's trapezoidal recursion as a plain loop over accelerations a_j,
  // from p0 = (0, 0) and a given v0; returns the endpoint of one axis.
  const double dt = 0.01;
  const int samples = run.size();
  auto endpoint_of = [&](const std::vector<double>& a, double v0) {
    return testing::PlainTrapezoidEndpoint(a, dt, v0);
  };
  std::vector<double> corrected[2];
  std::vector<double> raw[2] = {run.measured_x, run.measured_y};
  const Parameter bias[2] = {Parameter::kBiasX, Parameter::kBiasY};
  const Parameter scale[2] = {Parameter::kScaleX, Parameter::kScaleY};
  const double v0[2] = {1.0, 3.0};
  const double stated_variance[2] = {0.25, 0.64};
  double expected_endpoint[2];
  double expected_raw[2];
  double expected_parameter_part[2];
  double expected_noise_part[2];
  for (int axis = 0; axis < 2; ++axis) {
    const double b = course.fit.Value(bias[axis]);
    const double one_plus_s = 1 + course.fit.Value(scale[axis]);
    std::vector<double> d_bias(samples);
    std::vector<double> d_scale(samples);
    for (int j = 0; j < samples; ++j) {
      corrected[axis].push_back((raw[axis][j] - b) / one_plus_s);
      d_bias[j] = -1.0 / one_plus_s;                                 // d a_j / d b
      d_scale[j] = -(raw[axis][j] - b) / (one_plus_s * one_plus_s);  // d a_j / d s
    }
    expected_endpoint[axis] = endpoint_of(corrected[axis], v0[axis]);
    expected_raw[axis] = endpoint_of(raw[axis], v0[axis]);
    // The parameter part: J Sigma J^T with J from the derivatives of a_j (the endpoint is
    // linear in the a_j), Sigma the fit's (bias, scale) block of this axis.
    const Eigen::Vector2d jacobian(endpoint_of(d_bias, 0.0), endpoint_of(d_scale, 0.0));
    Eigen::Matrix2d block;
    block << course.fit.Covariance(bias[axis], bias[axis]),
        course.fit.Covariance(bias[axis], scale[axis]),
        course.fit.Covariance(scale[axis], bias[axis]),
        course.fit.Covariance(scale[axis], scale[axis]);
    expected_parameter_part[axis] = jacobian.dot(block * jacobian);
    // The noise part: sum_j w_j^2 sigma^2 / (1 + s)^2, w_j the endpoint's response to a
    // unit impulse at sample j (brute force, one recursion per sample).
    double sum_w2 = 0.0;
    std::vector<double> impulse(samples, 0.0);
    for (int j = 0; j < samples; ++j) {
      impulse[j] = 1.0;
      const double w = endpoint_of(impulse, 0.0);
      impulse[j] = 0.0;
      sum_w2 += w * w;
    }
    expected_noise_part[axis] = sum_w2 * stated_variance[axis] / (one_plus_s * one_plus_s);
  }
  EXPECT_NEAR(result.endpoint.x(), expected_endpoint[0], 1e-6);
  EXPECT_NEAR(result.endpoint.y(), expected_endpoint[1], 1e-6);
  EXPECT_NEAR(result.raw_endpoint.x(), expected_raw[0], 1e-6);
  EXPECT_NEAR(result.raw_endpoint.y(), expected_raw[1], 1e-6);
  EXPECT_NEAR(result.parameter_part(0, 0), expected_parameter_part[0],
              1e-9 * expected_parameter_part[0]);
  EXPECT_NEAR(result.parameter_part(1, 1), expected_parameter_part[1],
              1e-9 * expected_parameter_part[1]);
  EXPECT_NEAR(result.noise_part(0, 0), expected_noise_part[0], 1e-9 * expected_noise_part[0]);
  EXPECT_NEAR(result.noise_part(1, 1), expected_noise_part[1], 1e-9 * expected_noise_part[1]);
  // And the closed form sigma^2 dt T^3 / 3 / (1 + s)^2, within the discretisation's 0.1%.
  const double t3 = std::pow(59.99, 3);
  EXPECT_NEAR(result.noise_part(0, 0) /
                  (0.25 * dt * t3 / 3 / std::pow(1 + course.fit.Value(Parameter::kScaleX), 2)),
              1.0, 3e-3);
  EXPECT_NEAR(result.noise_part(1, 1) /
                  (0.64 * dt * t3 / 3 / std::pow(1 + course.fit.Value(Parameter::kScaleY), 2)),
              1.0, 3e-3);

  // C's distance from the independent endpoint under the independent covariance (the
  // cross terms are zero to 1e-3 m^2: the x endpoint depends on x's parameters only, and the
  // fit's x-y covariance is 0); p-value of chi^2 with 2 dof: exp(-d^2 / 2).
  ASSERT_EQ(landmarks[2].name, "C");
  const double dx = landmarks[2].x_m - expected_endpoint[0];
  const double dy = landmarks[2].y_m - expected_endpoint[1];
  const double total[2] = {expected_parameter_part[0] + expected_noise_part[0],
                           expected_parameter_part[1] + expected_noise_part[1]};
  const double c_distance2 = dx * dx / total[0] + dy * dy / total[1];
  const double c_parameters_only =
      dx * dx / expected_parameter_part[0] + dy * dy / expected_parameter_part[1];
  const LandmarkDecision decision =
      DecideLandmark(result.endpoint, result.covariance, landmarks, 0.01);
  EXPECT_EQ(decision.reached, "C");
  EXPECT_NEAR(decision.scores[2].mahalanobis2, 0.910, 1e-3);
  EXPECT_NEAR(decision.scores[2].mahalanobis2, c_distance2, 1e-4 * c_distance2);
  EXPECT_GT(decision.scores[2].posterior, 0.999999);
  EXPECT_NEAR(decision.scores[2].p_value, 0.634, 1e-3);
  EXPECT_NEAR(decision.scores[2].p_value, std::exp(-c_distance2 / 2), 1e-4);
  // Without the run's own noise (the other group bounded only the parameter terms), the
  // ellipse is 2.3 times too small per axis: C's squared distance grows from 0.91 to 4.95
  // (p = 0.084). C still passes here, but a 95% ellipse drawn that way covers the truth
  // far less than 95% of the time (see trajectory_test's Monte Carlo).
  const LandmarkDecision parameters_only =
      DecideLandmark(result.endpoint, result.parameter_part, landmarks, 0.01);
  EXPECT_NEAR(parameters_only.scores[2].mahalanobis2, 4.95, 0.01);
  EXPECT_NEAR(parameters_only.scores[2].mahalanobis2, c_parameters_only, 1e-4 * c_parameters_only);
  EXPECT_NEAR(std::sqrt(result.covariance(0, 0) / result.parameter_part(0, 0)), 2.33, 0.01);
  EXPECT_NEAR(std::sqrt(result.covariance(0, 0) / result.parameter_part(0, 0)),
              std::sqrt(total[0] / expected_parameter_part[0]), 1e-6);

  const auto budget = ComputeErrorBudget(result, course.fit, run, course.conditions);
  EXPECT_STREQ(budget[0].dominant, "noise");
  EXPECT_STREQ(budget[1].dominant, "noise");
  EXPECT_NEAR(budget[0].noise.three_sigma_m / budget[0].noise.report_m, 27.7, 0.05);
  EXPECT_NEAR(budget[1].noise.three_sigma_m / budget[1].noise.report_m, 26.6, 0.05);
  // Independent: 3 sqrt(noise part) against the report's 3 sigma_eta (one sample's noise).
  EXPECT_NEAR(budget[0].noise.three_sigma_m, 3 * std::sqrt(expected_noise_part[0]), 1e-6);
  EXPECT_NEAR(budget[1].noise.three_sigma_m, 3 * std::sqrt(expected_noise_part[1]), 1e-6);
  EXPECT_NEAR(budget[0].noise.report_m, 3 * std::sqrt(0.25), 1e-12);
  EXPECT_NEAR(budget[1].noise.report_m, 3 * std::sqrt(0.64), 1e-12);
}

}  // namespace
}  // namespace accelcal
