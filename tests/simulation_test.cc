// The simulator: portable randomness, the scenario format, the course's setting
// reproduced, each effect's signature in the baseline's residuals, data that round-trips
// through the course layout, and Monte Carlo results independent of the thread count.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <vector>

#include "common/format.h"
#include "estimation/linear_ls.h"
#include "io/course_data.h"
#include "io/mat_file.h"
#include "io/run_conditions.h"
#include "models/tilt_table.h"
#include "simulation/embedded_scenarios.h"
#include "simulation/monte_carlo.h"
#include "simulation/random.h"
#include "simulation/scenario.h"
#include "studies/coverage_study.h"
#include "test_support.h"

namespace accelcal {
namespace {

TEST(RandomSource, MatchesAnIndependentImplementationOfXoshiro256PlusPlus) {
  // Reference values from a separate Python implementation of splitmix64 seeding and
  // xoshiro256++: the same seed gives the same data on any machine and library.
  RandomSource random(42, 0);
  EXPECT_EQ(random.NextUint64(), 0x5b5e4a1bffcbb2f3ull);
  EXPECT_EQ(random.NextUint64(), 0xdad6b47570f6111dull);
  EXPECT_EQ(random.NextUint64(), 0xaa41d8357b710b2full);
  RandomSource stream(42, 7);
  EXPECT_EQ(stream.NextUint64(), 0x0d9893fc677d6169ull);
  RandomSource uniform(42, 0);
  EXPECT_EQ(uniform.Uniform(), 0.35690749343466055);
  EXPECT_EQ(uniform.Uniform(), 0.8548386370393575);
}

TEST(RandomSource, StandardNormalHasTheRightMomentsAndTails) {
  RandomSource random(3);
  const int n = 1000000;
  double sum = 0, sum2 = 0, sum4 = 0;
  int beyond = 0;
  for (int i = 0; i < n; ++i) {
    const double z = random.StandardNormal();
    sum += z;
    sum2 += z * z;
    sum4 += z * z * z * z;
    beyond += std::abs(z) > 1.959963984540054;
  }
  EXPECT_NEAR(sum / n, 0.0, 5 * std::sqrt(1.0 / n));
  EXPECT_NEAR(sum2 / n, 1.0, 5 * std::sqrt(2.0 / n));
  EXPECT_NEAR(sum4 / n, 3.0, 5 * std::sqrt(96.0 / n));
  EXPECT_NEAR(beyond / static_cast<double>(n), 0.05, 5 * std::sqrt(0.05 * 0.95 / n));
}

TEST(Scenario, TheEmbeddedCourseScenarioEndsExactlyAtC) {
  // The course's C = (459.84, 59.99) is where the piecewise profile read off the
  // corrected run ends when integrated from v0 = (1, 3): the data's hidden truth.
  Scenario scenario;
  ASSERT_TRUE(LoadDefaultScenario(&scenario).ok());
  const SimulatedData data = SimulateScenario(scenario, 1);
  EXPECT_EQ(data.test.size(), 20001);
  EXPECT_EQ(data.run.size(), 6000);
  EXPECT_NEAR(data.run.timestamp_s.back(), 59.99, 1e-12);
  EXPECT_EQ(data.reached_landmark, "C");
  EXPECT_LT(data.reached_distance_m, 1e-9);
  EXPECT_EQ(data.conditions.initial_velocity_y_mps, 3.0);
}

TEST(Scenario, TheEmbeddedScenarioIsTheFileInData) {
  const std::string path = std::string(ACCELCAL_SOURCE_DIR) + "/data/scenarios/tp2-2018.json";
  EXPECT_EQ(testing::ReadText(path), DefaultScenarioJson());
}

TEST(Scenario, RefusesUnknownKeysAndIncompleteProfiles) {
  Scenario scenario;
  const std::string run =
      R"("run": {"dt": 0.01, "duration": 1, "profile": {"segments": [{"duration": 1, "acceleration": [0, 0]}]}})";
  const std::string landmarks = R"("landmarks": {"listed": [{"name": "A", "position": [0, 0]}]})";
  EXPECT_TRUE(ParseScenario("{" + run + "," + landmarks + "}", ".", &scenario).ok());
  auto message = [&](const std::string& text) {
    return ParseScenario(text, ".", &scenario).message();
  };
  EXPECT_NE(message("{" + run + "," + landmarks + R"(, "noise_varaince": [1, 1]})")
                .find("unknown key \"noise_varaince\""),
            std::string::npos);
  EXPECT_NE(message("{" + run + "," + landmarks + R"(, "truth": {"angle_ofset": 0.1}})")
                .find("'angle_ofset' is not a parameter"),
            std::string::npos);
  EXPECT_NE(
      message(
          R"({"run": {"dt": 0.01, "duration": 2, "profile": {"segments": [{"duration": 1, "acceleration": [0, 0]}]}},)" +
          landmarks + "}")
          .find("cover 1 s of a 2 s run"),
      std::string::npos);
  EXPECT_NE(message("{" + run + R"(, "landmarks": {"listed": []}})").find("non-empty"),
            std::string::npos);
  EXPECT_NE(message("{" + run + "," + landmarks + R"(, "tilt": {"schedule": "spiral"}})")
                .find("expected uniform, static or list"),
            std::string::npos);
}

TEST(Scenario, OverridesSetEffectsAndSettingsByName) {
  Scenario scenario;
  ASSERT_TRUE(LoadDefaultScenario(&scenario).ok());
  ASSERT_TRUE(ApplyScenarioOverrides(
                  "angle_offset=0.004,bias_drift_x=0.1,tilt_samples=101,gravity=9.81", &scenario)
                  .ok());
  EXPECT_EQ(scenario.truth.parameters[Parameter::kAngleOffset], 0.004);
  EXPECT_EQ(scenario.truth.parameters[Parameter::kBiasDriftX], 0.1);
  EXPECT_EQ(scenario.tilt.sample_count, 101);
  EXPECT_EQ(scenario.truth.gravity_mps2, 9.81);
  EXPECT_NE(
      ApplyScenarioOverrides("angle=1", &scenario).message().find("'angle' is neither a parameter"),
      std::string::npos);
  EXPECT_NE(
      ApplyScenarioOverrides("noise_variance_x=-1", &scenario).message().find("must be positive"),
      std::string::npos);
  EXPECT_NE(ApplyScenarioOverrides("run_duration=90", &scenario)
                .message()
                .find("cover 60 s of the 90 s run"),
            std::string::npos);
}

TEST(Scenario, ARunProfileFromCsvIsReadExactly) {
  testing::ScratchDir scratch;
  std::string csv = "t,ax,ay\n";
  for (int j = 0; j < 300; ++j) csv += StringPrintf("%.2f,%g,%g\n", 0.01 * j, 0.001 * j, -0.5);
  scratch.Write("profile.csv", csv);
  scratch.Write("s.json", R"({"run": {"dt": 0.01, "duration": 3, "profile": {"csv": "profile.csv"}},
                             "landmarks": {"listed": [{"name": "A", "position": [0, 0]}]}})");
  Scenario scenario;
  const Status status = LoadScenario(scratch.File("s.json"), &scenario);
  ASSERT_TRUE(status.ok()) << status.message();
  std::vector<double> t;
  std::vector<double> ax;
  std::vector<double> ay;
  TrueRunAcceleration(scenario.run, &t, &ax, &ay);
  ASSERT_EQ(t.size(), 300u);
  EXPECT_EQ(ax[123], 0.123);
  EXPECT_EQ(ay[299], -0.5);
  // A profile whose rows do not match the run is refused with the file and the counts.
  scratch.Write("s.json", R"({"run": {"dt": 0.01, "duration": 4, "profile": {"csv": "profile.csv"}},
                             "landmarks": {"listed": [{"name": "A", "position": [0, 0]}]}})");
  EXPECT_NE(LoadScenario(scratch.File("s.json"), &scenario)
                .message()
                .find("profile.csv: 300 rows, but the run has 400 samples"),
            std::string::npos);
}

TEST(Scenario, StaticScheduleSplitsSamplesEvenly) {
  TiltSchedule schedule;
  schedule.kind = TiltSchedule::Kind::kStaticPositions;
  schedule.positions_rad = {0.0, 1.0, 2.0};
  schedule.sample_count = 8;
  EXPECT_EQ(TiltAngles(schedule), (std::vector<double>{0, 0, 1, 1, 1, 2, 2, 2}));
}

TEST(Scenario, DecoysHideTheTrueEndpointAtLeastTheMinimumDistanceApart) {
  Scenario scenario;
  ASSERT_TRUE(LoadDefaultScenario(&scenario).ok());
  scenario.landmarks = LandmarkSpec();
  scenario.landmarks.decoys = true;
  scenario.landmarks.decoy_count = 4;
  scenario.landmarks.decoy_min_distance_m = 80.0;
  const SimulatedData data = SimulateScenario(scenario, 9);
  ASSERT_EQ(data.landmarks.size(), 5u);
  EXPECT_LT(data.reached_distance_m, 1e-9);
  for (size_t a = 0; a < data.landmarks.size(); ++a) {
    for (size_t b = a + 1; b < data.landmarks.size(); ++b) {
      const double distance = std::hypot(data.landmarks[a].x_m - data.landmarks[b].x_m,
                                         data.landmarks[a].y_m - data.landmarks[b].y_m);
      EXPECT_GE(distance, 80.0);
    }
  }
}

TEST(Simulate, WrittenCourseLayoutReadsBackLikeTheCourseFilesAndRecoversTheTruth) {
  Scenario scenario;
  ASSERT_TRUE(LoadDefaultScenario(&scenario).ok());
  const SimulatedData data = SimulateScenario(scenario, 21);
  testing::ScratchDir mat_dir;
  testing::ScratchDir csv_dir;
  std::vector<std::string> written;
  ASSERT_TRUE(WriteDataDirectory(mat_dir.path(), DataLayout::kCourseMat, data.test, data.run,
                                 data.landmarks, data.conditions, &written)
                  .ok());
  ASSERT_TRUE(WriteDataDirectory(csv_dir.path(), DataLayout::kCsv, data.test, data.run,
                                 data.landmarks, data.conditions, &written)
                  .ok());
  for (const std::string& dir : {mat_dir.path(), csv_dir.path()}) {
    DataFiles files;
    ASSERT_TRUE(ResolveDataFiles(dir, &files).ok());
    CourseData loaded;
    ASSERT_TRUE(LoadDataFiles(files, &loaded).ok());
    const CalibrationTest& test = loaded.test;
    const VehicleRun& run = loaded.run;
    const std::vector<Landmark>& landmarks = loaded.landmarks;
    const RunConditions& conditions = loaded.conditions;
    // Exactly what was simulated, bit for bit.
    EXPECT_EQ(test.theta_rad, data.test.theta_rad);
    EXPECT_EQ(test.measured_y, data.test.measured_y);
    EXPECT_EQ(run.measured_x, data.run.measured_x);
    EXPECT_EQ(run.timestamp_s, data.run.timestamp_s);
    ASSERT_EQ(landmarks.size(), 4u);
    EXPECT_EQ(landmarks[2].x_m, data.landmarks[2].x_m);
    EXPECT_EQ(conditions.noise_variance_y, 0.64);
    LinearLsOptions options;
    options.noise_variance_x = conditions.noise_variance_x;
    options.noise_variance_y = conditions.noise_variance_y;
    BaselineFit fit;
    ASSERT_TRUE(EstimateLinearLs(test, options, &fit).ok());
    const ModelParameters<double>& truth = scenario.truth.parameters;
    const Eigen::Vector4d z =
        (fit.parameters - Eigen::Vector4d(truth[Parameter::kBiasX], truth[Parameter::kScaleX],
                                          truth[Parameter::kBiasY], truth[Parameter::kScaleY]))
            .cwiseQuotient(fit.StandardDeviations());
    EXPECT_LT(z.cwiseAbs().maxCoeff(), 3.0) << z.transpose();
  }
  // The .mat files hold what the course's hold: the same variables, shapes and class.
  ACCELCAL_REQUIRE_COURSE_DATA(course);
  for (const char* file : {"ensayo.mat", "acel.mat", "puntos.mat"}) {
    MatFileReader ours;
    MatFileReader theirs;
    ASSERT_TRUE(ours.Open(mat_dir.File(file)).ok());
    ASSERT_TRUE(theirs.Open(course + "/" + file).ok());
    std::vector<std::string> our_names;
    std::vector<std::string> their_names;
    ASSERT_TRUE(ours.ListVariables(&our_names).ok());
    ASSERT_TRUE(theirs.ListVariables(&their_names).ok());
    EXPECT_EQ(our_names, their_names) << file;
    for (const std::string& name : their_names) {
      MatMatrix a;
      MatMatrix b;
      ASSERT_TRUE(ours.ReadMatrix(name, &a).ok());
      ASSERT_TRUE(theirs.ReadMatrix(name, &b).ok());
      EXPECT_EQ(a.rows, b.rows) << file << " " << name;
      EXPECT_EQ(a.cols, b.cols) << file << " " << name;
    }
  }
  EXPECT_EQ(testing::ReadText(mat_dir.File("datos.txt")),
            testing::ReadText(course + "/datos.txt") + "\n");
}

// Each effect alone, in a noisy course-sized test, leaves its own signature in the
// baseline's residuals: the residual regressed on the predicted shape recovers the
// predicted amplitude (within 4 sigma), and the other axis shows nothing. Sizes are
// chosen to be about 10 sigma of their signature.
struct Signature {
  const char* effect;
  double size;
  bool x_axis;                                // the axis the effect shows in
  std::function<double(double theta)> shape;  // residual shape
  double amplitude_per_size;                  // predicted amplitude / size
};

class EffectSignatureTest : public ::testing::TestWithParam<int> {};

std::vector<Signature> Signatures() {
  const double g = 9.8;
  const double one_plus_sx = 1.0 - 3.014e-2;
  const double one_plus_sy = 1.0 + 1.004e-2;
  return {
      // sin(theta + d) ~ sin(theta) + d cos(theta): fx gains -g d cos(theta).
      {"angle_offset", 0.01, true, [](double t) { return std::cos(t); }, -one_plus_sx * g},
      // cos(theta + d) ~ cos(theta) - d sin(theta): fy gains +g d sin(theta).
      {"angle_offset", 0.01, false, [](double t) { return std::sin(t); }, one_plus_sy * g},
      // f_along_y gains fx sin(eps) = -g eps sin(theta); x is the reference axis.
      {"nonorthogonality", 0.01, false, [](double t) { return std::sin(t); }, -one_plus_sy * g},
      // k2 f^2 = k2 g^2 sin^2 = k2 g^2 (1 - cos 2 theta)/2: the constant goes into the bias.
      {"scale_nonlinearity_x", 0.002, true, [](double t) { return std::cos(2 * t); }, -g * g / 2},
      {"scale_nonlinearity_y", 0.002, false, [](double t) { return std::cos(2 * t); }, g * g / 2},
      // d u, u = theta/(2 pi) - 1/2 on this schedule. The baseline absorbs u's projection
      // on sin(theta), which is -sin(theta)/pi, into scale_x; the rest remains.
      {"bias_drift_x", 0.2, true,
       [](double t) { return t / (2 * M_PI) - 0.5 + std::sin(t) / M_PI; }, 1.0},
      // For y the regressor is cos(theta), orthogonal to u: the whole ramp remains.
      {"bias_drift_y", 0.2, false, [](double t) { return t / (2 * M_PI) - 0.5; }, 1.0},
  };
}

TEST_P(EffectSignatureTest, ShowsInTheBaselineResidualAsPredicted) {
  const Signature signature = Signatures()[GetParam()];
  SimulationTruth truth = CourseTableOneTruth();
  truth.parameters[FindParameter(signature.effect)->parameter] = signature.size;
  TiltSchedule schedule;
  schedule.sample_count = 20001;
  const CalibrationTest test = SimulateTiltTest(schedule, truth, 31);
  LinearLsOptions options;
  options.noise_variance_x = 0.25;
  options.noise_variance_y = 0.64;
  BaselineFit fit;
  ASSERT_TRUE(EstimateLinearLs(test, options, &fit).ok());
  for (const bool x_axis : {true, false}) {
    // Residual of the baseline fit on this axis, regressed on the shape.
    double shape_residual = 0.0;
    double shape_shape = 0.0;
    for (int i = 0; i < test.size(); ++i) {
      double fx;
      double fy;
      TiltTableSpecificForce(test.theta_rad[i], 9.8, &fx, &fy);
      const double residual =
          x_axis
              ? test.measured_x[i] - ((1 + fit.parameters[kScaleX]) * fx + fit.parameters[kBiasX])
              : test.measured_y[i] - ((1 + fit.parameters[kScaleY]) * fy + fit.parameters[kBiasY]);
      const double shape = signature.shape(test.theta_rad[i]);
      shape_residual += shape * residual;
      shape_shape += shape * shape;
    }
    const double amplitude = shape_residual / shape_shape;
    const double sigma = std::sqrt((x_axis ? 0.25 : 0.64) / shape_shape);
    const double expected =
        x_axis == signature.x_axis ? signature.amplitude_per_size * signature.size : 0.0;
    EXPECT_NEAR(amplitude, expected, 4 * sigma)
        << signature.effect << " on " << (x_axis ? "x" : "y") << ": amplitude " << amplitude
        << " +- " << sigma;
    if (x_axis == signature.x_axis) {
      EXPECT_GT(std::abs(amplitude), 5 * sigma) << "the signature must stand out of the noise";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(EveryCalibrationEffect, EffectSignatureTest, ::testing::Range(0, 7));

TEST(EffectSignature, RunBiasShiftLeavesTheTestAloneAndNoiseRatioScalesChiSquare) {
  SimulationTruth truth = CourseTableOneTruth();
  truth.parameters[Parameter::kRunBiasShiftX] = 0.5;
  truth.parameters[Parameter::kNoiseVarianceY] = 1.5;
  TiltSchedule schedule;
  schedule.sample_count = 20001;
  const CalibrationTest with_effects = SimulateTiltTest(schedule, truth, 5);
  const CalibrationTest without = SimulateTiltTest(schedule, CourseTableOneTruth(), 5);
  EXPECT_EQ(with_effects.measured_x, without.measured_x);  // r_x exists only in the run
  LinearLsOptions options;
  options.noise_variance_x = 0.25;
  options.noise_variance_y = 0.64;
  BaselineFit fit;
  ASSERT_TRUE(EstimateLinearLs(with_effects, options, &fit).ok());
  EXPECT_NEAR(fit.chi2_y.chi2 / fit.chi2_y.dof, 1.5, 5 * 1.5 * std::sqrt(2.0 / 20001));
  // In the run, r_x shifts every x output by exactly 0.5.
  const std::vector<double> t = {0.0, 0.01, 0.02};
  const std::vector<double> a = {1.0, 2.0, 3.0};
  const VehicleRun shifted = SimulateVehicleRun(t, a, a, truth, 8);
  SimulationTruth no_shift = truth;
  no_shift.parameters[Parameter::kRunBiasShiftX] = 0.0;
  const VehicleRun plain = SimulateVehicleRun(t, a, a, no_shift, 8);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(shifted.measured_x[j] - plain.measured_x[j], 0.5, 1e-12);
}

TEST(MonteCarlo, ResultsDoNotDependOnTheThreadCount) {
  Scenario scenario;
  ASSERT_TRUE(LoadDefaultScenario(&scenario).ok());
  ASSERT_TRUE(ApplyScenarioOverrides("tilt_samples=500,run_duration=10", &scenario).ok());
  CoverageOptions options;
  options.trials = 60;
  options.seed = 4;
  options.progress = false;
  options.threads = 1;
  const CoverageResult one = RunCoverageStudy(scenario, options);
  options.threads = 2;
  const CoverageResult two = RunCoverageStudy(scenario, options);
  options.threads = 5;
  const CoverageResult five = RunCoverageStudy(scenario, options);
  EXPECT_EQ(two.threads, 2);
  for (int i = 0; i < kBaselineParameterCount; ++i) {
    EXPECT_EQ(one.parameters[i].mean, two.parameters[i].mean);
    EXPECT_EQ(one.parameters[i].mean, five.parameters[i].mean);
    EXPECT_EQ(one.parameters[i].empirical_sd, five.parameters[i].empirical_sd);
  }
  EXPECT_EQ(one.endpoint_ellipse_coverage, five.endpoint_ellipse_coverage);
  // Every trial runs exactly once.
  std::vector<int> calls(1000, 0);
  MonteCarloOptions monte_carlo;
  monte_carlo.trials = 1000;
  monte_carlo.threads = 2;
  monte_carlo.progress = false;
  RunTrials(monte_carlo, [&](int trial) { ++calls[trial]; });
  EXPECT_EQ(std::count(calls.begin(), calls.end(), 1), 1000);
}

// The coverage study on the course-sized baseline: the reported covariance is right.
// 600 trials: a 95% coverage has a binomial sd of 0.9% (tolerance 3%), a 68% one 1.9%
// (tolerance 5%), an sd ratio about 2.9% (tolerance 10%).
TEST(CoverageStudy, TheBaselinesReportedCovarianceIsRightOnTheCourseScenario) {
  Scenario scenario;
  ASSERT_TRUE(LoadDefaultScenario(&scenario).ok());
  CoverageOptions options;
  options.trials = 600;
  options.seed = 12;
  options.progress = false;
  const CoverageResult result = RunCoverageStudy(scenario, options);
  ASSERT_EQ(result.trials, 600);
  for (int i = 0; i < kBaselineParameterCount; ++i) {
    const ParameterCoverage& row = result.parameters[i];
    EXPECT_NEAR(row.empirical_sd / row.reported_sd, 1.0, 0.10) << kBaselineParameterNames[i];
    EXPECT_LT(std::abs(row.bias_sigma), 4.0 / std::sqrt(600.0)) << kBaselineParameterNames[i];
    EXPECT_NEAR(row.interval_coverage[0], 0.68, 0.05) << kBaselineParameterNames[i];
    EXPECT_NEAR(row.interval_coverage[1], 0.95, 0.03) << kBaselineParameterNames[i];
  }
  for (int axis = 0; axis < 2; ++axis)
    EXPECT_NEAR(result.axis_ellipse_coverage[axis][1], 0.95, 0.03);
  EXPECT_NEAR(result.endpoint_ellipse_coverage[1], 0.95, 0.03);
  EXPECT_NEAR(result.mean_chi2_per_dof.x(), 1.0, 0.005);
}

TEST(CoverageStudy, AHiddenEffectBiasesWhatItShould) {
  Scenario scenario;
  ASSERT_TRUE(LoadDefaultScenario(&scenario).ok());
  CoverageOptions options;
  options.trials = 100;
  options.progress = false;
  // bias_drift_x leaks into scale_x through the sin(theta) projection (see the signature
  // test): about d / (pi g sigma_s) = 0.1 / (pi 9.8 5.1e-4) = 6.4 sigma.
  ASSERT_TRUE(ApplyScenarioOverrides("bias_drift_x=0.1", &scenario).ok());
  CoverageResult result = RunCoverageStudy(scenario, options);
  EXPECT_NEAR(result.parameters[kScaleX].bias_sigma, 0.1 / (M_PI * 9.8 * 5.102e-4), 0.5);
  EXPECT_LT(result.parameters[kScaleX].interval_coverage[1], 0.2);
  EXPECT_NEAR(result.parameters[kBiasX].bias_sigma, 0.0, 0.5);
  // A run bias shift never touches the test but moves the endpoint by r T^2/2 / sigma.
  ASSERT_TRUE(ApplyScenarioOverrides("bias_drift_x=0,run_bias_shift_x=0.02", &scenario).ok());
  result = RunCoverageStudy(scenario, options);
  EXPECT_NEAR(result.parameters[kBiasX].bias_sigma, 0.0, 0.5);
  EXPECT_NEAR(result.endpoint_bias_sigma.x(), 0.02 * 59.99 * 59.99 / 2 / 0.97 / std::sqrt(234.3),
              0.5);
}

}  // namespace
}  // namespace accelcal
