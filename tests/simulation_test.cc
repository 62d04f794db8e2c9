// The simulator: portable randomness, the scenario format, the course's setting
// reproduced, each effect's signature in the baseline's residuals, data that round-trips
// through the course layout, Monte Carlo results independent of the thread count, and the
// disturbances outside the catalogue (their statistics, and no change when neutral).

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <vector>

#include "common/format.h"
#include "common/tilt_motion.h"
#include "estimation/tilt_table/linear_ls.h"
#include "io/course_data.h"
#include "io/mat_file.h"
#include "io/run_conditions.h"
#include "io/scenario_json.h"
#include "models/sensor_model.h"
#include "models/tilt_table.h"
#include "simulation/disturbances.h"
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
    LinearLsOptions options = LinearLsOptionsFor(conditions, kCourseGravityMps2);
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
              ? test.measured_x[i] - ((1 + fit.parameters[BaselineIndex(Parameter::kScaleX)]) * fx +
                                      fit.parameters[BaselineIndex(Parameter::kBiasX)])
              : test.measured_y[i] - ((1 + fit.parameters[BaselineIndex(Parameter::kScaleY)]) * fy +
                                      fit.parameters[BaselineIndex(Parameter::kBiasY)]);
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

// Nor on whether the trials are counted for a progress line.
TEST(MonteCarlo, ResultsDoNotDependOnTheThreadCount) {
  Scenario scenario;
  ASSERT_TRUE(LoadDefaultScenario(&scenario).ok());
  ASSERT_TRUE(ApplyScenarioOverrides("tilt_samples=500,run_duration=10", &scenario).ok());
  CoverageOptions options;
  options.trials = 60;
  options.seed = 4;
  options.threads = 1;
  const CoverageResult one = RunCoverageStudy(scenario, options);
  options.threads = 2;
  const CoverageResult two = RunCoverageStudy(scenario, options);
  options.threads = 5;
  int64_t counted = 0;
  options.progress = [&](int64_t done, int64_t) { counted = done; };
  const CoverageResult five = RunCoverageStudy(scenario, options);
  EXPECT_EQ(counted, 60);
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
  const CoverageResult result = RunCoverageStudy(scenario, options);
  ASSERT_EQ(result.trials, 600);
  for (int i = 0; i < kBaselineParameterCount; ++i) {
    const ParameterCoverage& row = result.parameters[i];
    EXPECT_NEAR(row.empirical_sd / row.reported_sd, 1.0, 0.10) << Info(kBaselineParameters[i]).name;
    EXPECT_LT(std::abs(row.bias_sigma), 4.0 / std::sqrt(600.0))
        << Info(kBaselineParameters[i]).name;
    EXPECT_NEAR(row.interval_coverage[0], 0.68, 0.05) << Info(kBaselineParameters[i]).name;
    EXPECT_NEAR(row.interval_coverage[1], 0.95, 0.03) << Info(kBaselineParameters[i]).name;
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
  // bias_drift_x leaks into scale_x through the sin(theta) projection (see the signature
  // test): about d / (pi g sigma_s) = 0.1 / (pi 9.8 5.1e-4) = 6.4 sigma.
  ASSERT_TRUE(ApplyScenarioOverrides("bias_drift_x=0.1", &scenario).ok());
  CoverageResult result = RunCoverageStudy(scenario, options);
  EXPECT_NEAR(result.parameters[BaselineIndex(Parameter::kScaleX)].bias_sigma,
              0.1 / (M_PI * 9.8 * 5.102e-4), 0.5);
  EXPECT_LT(result.parameters[BaselineIndex(Parameter::kScaleX)].interval_coverage[1], 0.2);
  EXPECT_NEAR(result.parameters[BaselineIndex(Parameter::kBiasX)].bias_sigma, 0.0, 0.5);
  // A run bias shift never touches the test but moves the endpoint by r T^2/2 / sigma.
  ASSERT_TRUE(ApplyScenarioOverrides("bias_drift_x=0,run_bias_shift_x=0.02", &scenario).ok());
  result = RunCoverageStudy(scenario, options);
  EXPECT_NEAR(result.parameters[BaselineIndex(Parameter::kBiasX)].bias_sigma, 0.0, 0.5);
  EXPECT_NEAR(result.endpoint_bias_sigma.x(), 0.02 * 59.99 * 59.99 / 2 / 0.97 / std::sqrt(234.3),
              0.5);
}

// Disturbances: truths outside the catalogue (simulation/disturbances.h).

// The course scenario with `disturbances` as its "disturbances" object ("" for none).
Status CourseScenarioWith(const std::string& disturbances, Scenario* scenario) {
  std::string text = DefaultScenarioJson();
  if (!disturbances.empty()) text.insert(text.rfind('}'), ", \"disturbances\": " + disturbances);
  return ParseScenario(text, ".", scenario);
}

// Each axis's measured output minus the catalogue model's noiseless prediction.
void TiltTestResiduals(const CalibrationTest& test, const SimulationTruth& truth,
                       std::vector<double>* residual_x, std::vector<double>* residual_y) {
  CalibrationResiduals(test, truth.parameters, truth.gravity_mps2, residual_x, residual_y);
}

void RunResiduals(const VehicleRun& run, const std::vector<double>& acceleration_x,
                  const std::vector<double>& acceleration_y, const SimulationTruth& truth,
                  std::vector<double>* residual_x, std::vector<double>* residual_y) {
  residual_x->resize(run.size());
  residual_y->resize(run.size());
  for (int j = 0; j < run.size(); ++j) {
    double predicted_x;
    double predicted_y;
    PredictRunOutputs(acceleration_x[j], acceleration_y[j], truth.parameters, &predicted_x,
                      &predicted_y);
    (*residual_x)[j] = run.measured_x[j] - predicted_x;
    (*residual_y)[j] = run.measured_y[j] - predicted_y;
  }
}

// Moments of a zero-mean series.
struct SeriesMoments {
  double variance = 0.0;
  double lag1_correlation = 0.0;
  double excess_kurtosis = 0.0;
};

SeriesMoments Moments(const std::vector<double>& e) {
  double sum2 = 0.0;
  double sum4 = 0.0;
  double lagged = 0.0;
  for (size_t i = 0; i < e.size(); ++i) {
    sum2 += e[i] * e[i];
    sum4 += e[i] * e[i] * e[i] * e[i];
    if (i > 0) lagged += e[i] * e[i - 1];
  }
  const double n = static_cast<double>(e.size());
  SeriesMoments moments;
  moments.variance = sum2 / n;
  moments.lag1_correlation = lagged / sum2;
  moments.excess_kurtosis = (sum4 / n) / (moments.variance * moments.variance) - 3.0;
  return moments;
}

// The innovations e_i - rho e_{i-1} of an AR(1) series.
std::vector<double> Innovations(const std::vector<double>& e, double rho) {
  std::vector<double> innovations(e.size() - 1);
  for (size_t i = 1; i < e.size(); ++i) innovations[i - 1] = e[i] - rho * e[i - 1];
  return innovations;
}

// A long tilt test and a long run on the course's truth, with a stated variance ratio on y.
struct LongExperiment {
  static constexpr int kSamples = 200000;
  SimulationTruth truth = CourseTableOneTruth();
  TiltSchedule schedule;
  std::vector<double> timestamp_s;
  std::vector<double> acceleration_x;
  std::vector<double> acceleration_y;

  LongExperiment() {
    truth.parameters[Parameter::kNoiseVarianceY] = 1.5;
    schedule.sample_count = kSamples;
    for (int j = 0; j < kSamples; ++j) {
      timestamp_s.push_back(0.01 * j);
      acceleration_x.push_back(2.0 * std::sin(1e-3 * j));
      acceleration_y.push_back(-1.0 + 0.5 * std::cos(3e-4 * j));
    }
  }
  // The test's and the run's residuals, x then y.
  std::vector<std::vector<double>> Residuals(uint64_t seed) const {
    std::vector<std::vector<double>> residuals(4);
    TiltTestResiduals(SimulateTiltTest(schedule, truth, seed), truth, &residuals[0], &residuals[1]);
    RunResiduals(SimulateVehicleRun(timestamp_s, acceleration_x, acceleration_y, truth, seed),
                 acceleration_x, acceleration_y, truth, &residuals[2], &residuals[3]);
    return residuals;
  }
  double TrueVariance(int series) const {
    return series % 2 == 0 ? truth.TrueNoiseVarianceX() : truth.TrueNoiseVarianceY();
  }
};

TEST(Disturbances, NeutralOnesLeaveTheSimulationBitIdentical) {
  Scenario plain;
  ASSERT_TRUE(CourseScenarioWith("", &plain).ok());
  const SimulatedData reference = SimulateScenario(plain, 7, 3);
  for (const std::string& neutral :
       {std::string("{}"), std::string(R"({"noise_ar1": [0, 0]})"),
        std::string(R"({"noise_ar1": [0, 0], "outlier_fraction": 0, "outlier_sigma": 30,
                        "theta_harmonic": {"order": 3, "amplitude": [0, 0], "phase": 1},
                        "bias_step": {"at": 0.2, "size": [0, 0]}, "scale_cubic": [0, 0]})")}) {
    Scenario scenario;
    const Status status = CourseScenarioWith(neutral, &scenario);
    ASSERT_TRUE(status.ok()) << status.message();
    EXPECT_FALSE(scenario.truth.disturbances.any()) << neutral;
    const SimulatedData data = SimulateScenario(scenario, 7, 3);
    EXPECT_EQ(data.test.measured_x, reference.test.measured_x) << neutral;
    EXPECT_EQ(data.test.measured_y, reference.test.measured_y) << neutral;
    EXPECT_EQ(data.run.measured_x, reference.run.measured_x) << neutral;
    EXPECT_EQ(data.run.measured_y, reference.run.measured_y) << neutral;
    EXPECT_TRUE(data.outlier_indices_x.empty() && data.outlier_indices_y.empty());
    EXPECT_TRUE(TruthJson(scenario, data, 7)["disturbances"].is_null()) << neutral;
  }
}

TEST(Disturbances, Ar1NoiseHasItsCorrelationAndKeepsTheTrueVariance) {
  LongExperiment experiment;
  const double rho[2] = {0.6, -0.3};
  experiment.truth.disturbances.noise_ar1_x = rho[0];
  experiment.truth.disturbances.noise_ar1_y = rho[1];
  const std::vector<std::vector<double>> residuals = experiment.Residuals(41);
  const double n = LongExperiment::kSamples;
  for (int series = 0; series < 4; ++series) {
    const double r = rho[series % 2];
    const double variance = experiment.TrueVariance(series);
    const SeriesMoments moments = Moments(residuals[series]);
    // Bartlett: the lag-1 estimate of an AR(1) has variance (1 - rho^2) / N; the variance
    // estimate 2 sigma^4 (1 + rho^2) / ((1 - rho^2) N).
    EXPECT_NEAR(moments.lag1_correlation, r, 3 * std::sqrt((1 - r * r) / n)) << series;
    EXPECT_NEAR(moments.variance, variance,
                3 * variance * std::sqrt(2 * (1 + r * r) / ((1 - r * r) * n)))
        << series;
  }
}

TEST(Disturbances, StudentTNoiseHasTheTrueVarianceAndHeavyTails) {
  LongExperiment experiment;
  const LongExperiment gaussian = experiment;
  experiment.truth.disturbances.noise_student_t_dof = 5.0;
  const std::vector<std::vector<double>> residuals = experiment.Residuals(43);
  const std::vector<std::vector<double>> gaussian_residuals = gaussian.Residuals(43);
  const double n = LongExperiment::kSamples;
  for (int series = 0; series < 4; ++series) {
    const double variance = experiment.TrueVariance(series);
    const SeriesMoments moments = Moments(residuals[series]);
    // A t of 5 degrees of freedom has kurtosis 9: the variance estimate's sd is
    // sigma^2 sqrt(8 / N); its excess kurtosis is 6 (a Gaussian's 0).
    EXPECT_NEAR(moments.variance, variance, 5 * variance * std::sqrt(8.0 / n)) << series;
    EXPECT_GT(moments.excess_kurtosis, 1.0) << series;
    EXPECT_NEAR(Moments(gaussian_residuals[series]).excess_kurtosis, 0.0, 0.1) << series;
    // The numerators are the simulator's own normal draws: every sample keeps its sign.
    int same_sign = 0;
    for (size_t i = 0; i < residuals[series].size(); ++i)
      same_sign += (residuals[series][i] > 0) == (gaussian_residuals[series][i] > 0);
    EXPECT_EQ(same_sign, LongExperiment::kSamples) << series;
  }
  // With AR(1), the innovations are the t draws: heavy-tailed, the marginal variance kept.
  const double rho = 0.5;
  experiment.truth.disturbances.noise_ar1_x = rho;
  experiment.truth.disturbances.noise_ar1_y = rho;
  const std::vector<std::vector<double>> correlated = experiment.Residuals(45);
  for (int series = 0; series < 4; ++series) {
    const double variance = experiment.TrueVariance(series);
    const SeriesMoments moments = Moments(correlated[series]);
    EXPECT_NEAR(moments.lag1_correlation, rho, 4 * std::sqrt((1 - rho * rho) / n)) << series;
    EXPECT_NEAR(moments.variance, variance,
                5 * variance * std::sqrt(8.0 * (1 + rho * rho) / ((1 - rho * rho) * n)))
        << series;
    const SeriesMoments innovations = Moments(Innovations(correlated[series], rho));
    EXPECT_NEAR(innovations.variance, (1 - rho * rho) * variance,
                5 * (1 - rho * rho) * variance * std::sqrt(8.0 / n))
        << series;
    EXPECT_GT(innovations.excess_kurtosis, 1.0) << series;
  }
}

TEST(Disturbances, OutliersHitTheirFractionOfTheTestAndAreReportedInTheTruth) {
  Scenario scenario;
  ASSERT_TRUE(CourseScenarioWith("", &scenario).ok());
  ASSERT_TRUE(ApplyScenarioOverrides("tilt_samples=200000", &scenario).ok());
  const SimulatedData plain = SimulateScenario(scenario, 5);
  const double fraction = 0.05;
  const double k = 20.0;
  ASSERT_TRUE(ApplyScenarioOverrides("outlier_fraction=0.05,outlier_sigma=20", &scenario).ok());
  const SimulatedData data = SimulateScenario(scenario, 5);
  std::vector<double> residual_x;
  std::vector<double> residual_y;
  TiltTestResiduals(data.test, scenario.truth, &residual_x, &residual_y);
  const double n = data.test.size();
  const double count_sd = std::sqrt(n * fraction * (1 - fraction));
  const nlohmann::json truth = TruthJson(scenario, data, 5);
  ASSERT_TRUE(truth.contains("disturbances"));
  EXPECT_EQ(truth["disturbances"]["outlier_fraction"], fraction);
  EXPECT_EQ(truth["disturbances"]["outlier_sigma"], k);
  for (const bool x_axis : {true, false}) {
    const std::vector<int>& reported = x_axis ? data.outlier_indices_x : data.outlier_indices_y;
    const std::vector<double>& residual = x_axis ? residual_x : residual_y;
    const std::vector<double>& measured = x_axis ? data.test.measured_x : data.test.measured_y;
    const std::vector<double>& plain_measured =
        x_axis ? plain.test.measured_x : plain.test.measured_y;
    const double sigma = std::sqrt(x_axis ? scenario.truth.TrueNoiseVarianceX()
                                          : scenario.truth.TrueNoiseVarianceY());
    EXPECT_NEAR(reported.size(), fraction * n, 4 * count_sd);
    // A Gaussian sample never reaches (k - 5) sigma; an outlier always does.
    std::vector<int> large;
    int positive = 0;
    for (int i = 0; i < data.test.size(); ++i) {
      if (std::abs(residual[i]) > (k - 5) * sigma) {
        large.push_back(i);
        positive += residual[i] > 0;
      }
    }
    EXPECT_EQ(large, reported);
    EXPECT_NEAR(positive, 0.5 * reported.size(), 4 * std::sqrt(0.25 * reported.size()));
    // The outliers come from a stream of their own: every other sample is as without them.
    std::vector<bool> hit(data.test.size(), false);
    for (const int i : reported) hit[i] = true;
    int unchanged = 0;
    for (int i = 0; i < data.test.size(); ++i)
      unchanged += !hit[i] && measured[i] == plain_measured[i];
    EXPECT_EQ(unchanged, data.test.size() - static_cast<int>(reported.size()));
    EXPECT_EQ(truth["disturbances"][x_axis ? "outlier_indices_x" : "outlier_indices_y"],
              nlohmann::json(reported));
  }
  // Test only: the run is untouched.
  EXPECT_EQ(data.run.measured_x, plain.run.measured_x);
  EXPECT_EQ(data.run.measured_y, plain.run.measured_y);
}

TEST(Disturbances, HarmonicStepAndCubicScaleAddExactlyTheirTerms) {
  // With sigma = 1e-6 the measured output minus the catalogue's prediction is the added
  // term itself, sample by sample.
  Scenario scenario;
  ASSERT_TRUE(CourseScenarioWith(R"({"theta_harmonic": {"order": 3, "amplitude": [0.05, -0.02],
                                                          "phase": 0.4},
                                      "bias_step": {"at": 0.3, "size": [0.01, -0.03]},
                                      "scale_cubic": [1e-4, -2e-4]})",
                                 &scenario)
                  .ok());
  ASSERT_TRUE(ApplyScenarioOverrides("noise_variance_x_stated=1e-12,noise_variance_y_stated=1e-12,"
                                     "tilt_samples=1001,angle_offset=0.01",
                                     &scenario)
                  .ok());
  const SimulationTruth& truth = scenario.truth;
  const SimulatedData data = SimulateScenario(scenario, 17);
  std::vector<double> residual_x;
  std::vector<double> residual_y;
  TiltTestResiduals(data.test, truth, &residual_x, &residual_y);
  const double tolerance = 1e-5;  // 10 sigma
  const double g = truth.gravity_mps2;
  for (int i = 0; i < data.test.size(); ++i) {
    // The spec's forces at the true angle theta + delta; the step starts at floor(0.3 N).
    const double theta = data.test.theta_rad[i];
    const double force_x = -g * std::sin(theta + 0.01);
    const double force_y = -g * std::cos(theta + 0.01);
    const double harmonic = std::sin(3 * theta + 0.4);
    const bool stepped = i >= 300;
    EXPECT_NEAR(residual_x[i],
                0.05 * harmonic + (stepped ? 0.01 : 0.0) + 1e-4 * force_x * force_x * force_x,
                tolerance)
        << i;
    EXPECT_NEAR(residual_y[i],
                -0.02 * harmonic + (stepped ? -0.03 : 0.0) - 2e-4 * force_y * force_y * force_y,
                tolerance)
        << i;
  }
  // In the run only the cubic term acts, on the true acceleration.
  const std::vector<double> t = {0.0, 0.01, 0.02, 0.03};
  const std::vector<double> ax = {5.0, -3.0, 0.5, 8.0};
  const std::vector<double> ay = {-4.0, 2.0, 7.0, -0.1};
  const VehicleRun run = SimulateVehicleRun(t, ax, ay, truth, 17);
  std::vector<double> run_x;
  std::vector<double> run_y;
  RunResiduals(run, ax, ay, truth, &run_x, &run_y);
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(run_x[j], 1e-4 * ax[j] * ax[j] * ax[j], tolerance) << j;
    EXPECT_NEAR(run_y[j], -2e-4 * ay[j] * ay[j] * ay[j], tolerance) << j;
  }
}

// The shapes of issue 33, item 1: a warm-up and cool-down, a bias that depends on the turn,
// one held position offset, clipping at full scale; each adds exactly its term.
TEST(Disturbances, WarmUpHysteresisPositionOffsetAndFullScaleAddExactlyTheirTerms) {
  Scenario scenario;
  ASSERT_TRUE(CourseScenarioWith(R"({"bias_warmup": [0.2, 0],
                                      "bias_hysteresis": [0, -0.1],
                                      "position_offset": {"at": 0.3, "size": [0.05, 0.07]},
                                      "full_scale": [9.0, 0]})",
                                 &scenario)
                  .ok());
  ASSERT_TRUE(ApplyScenarioOverrides("noise_variance_x_stated=1e-12,noise_variance_y_stated=1e-12",
                                     &scenario)
                  .ok());
  // Ten positions going up, then the same ten coming down, 20 samples each.
  scenario.tilt.kind = TiltSchedule::Kind::kStaticPositions;
  scenario.tilt.sample_count = 400;
  for (int p = 0; p < 20; ++p) scenario.tilt.positions_rad.push_back((p < 10 ? p : 19 - p) * 0.6);
  const SimulationTruth& truth = scenario.truth;
  const SimulatedData data = SimulateScenario(scenario, 17);
  std::vector<double> residual_x;
  std::vector<double> residual_y;
  TiltTestResiduals(data.test, truth, &residual_x, &residual_y);
  const int n = data.test.size();
  double warmup_mean = 0.0;
  for (int i = 0; i < n; ++i) warmup_mean += std::sin(M_PI * i / (n - 1)) / n;
  const std::vector<double> direction = TurnDirection(data.test.theta_rad);
  const double tolerance = 1e-5;  // 10 sigma
  for (int i = 0; i < n; ++i) {
    // Sample floor(0.3 N) = 120 is in the seventh position, samples 120 to 139.
    const bool offset = i >= 120 && i < 140;
    double force_x = 0.0;
    double force_y = 0.0;
    CalibrationForcesAlongAxes(data.test.theta_rad[i], truth.gravity_mps2, truth.parameters,
                               &force_x, &force_y);
    const double clipped =
        std::abs(force_x) > 9.0 ? std::copysign(std::abs(force_x) - 9.0, force_x) : 0.0;
    EXPECT_NEAR(
        residual_x[i],
        0.2 * (std::sin(M_PI * i / (n - 1)) - warmup_mean) + (offset ? 0.05 : 0.0) - clipped,
        tolerance)
        << i;
    EXPECT_NEAR(residual_y[i], -0.05 * direction[i] + (offset ? 0.07 : 0.0), tolerance) << i;
  }
  EXPECT_EQ(direction.front(), 1.0);
  EXPECT_EQ(direction.back(), -1.0);
}

TEST(Disturbances, OverridesSetEachDisturbanceByName) {
  Scenario scenario;
  ASSERT_TRUE(CourseScenarioWith("", &scenario).ok());
  const Status status = ApplyScenarioOverrides(
      "noise_ar1_x=0.1,noise_ar1_y=-0.2,noise_student_t_dof=7.5,outlier_fraction=0.01,"
      "outlier_sigma=12,theta_harmonic_order=4,theta_harmonic_x=0.03,theta_harmonic_y=0.04,"
      "theta_harmonic_phase=-1,bias_step_at=0.25,bias_step_x=0.05,bias_step_y=0.06,"
      "scale_cubic_x=1e-5,scale_cubic_y=-3e-5",
      &scenario);
  ASSERT_TRUE(status.ok()) << status.message();
  const Disturbances& d = scenario.truth.disturbances;
  EXPECT_EQ(d.noise_ar1_x, 0.1);
  EXPECT_EQ(d.noise_ar1_y, -0.2);
  EXPECT_EQ(d.noise_student_t_dof, 7.5);
  EXPECT_EQ(d.outlier_fraction, 0.01);
  EXPECT_EQ(d.outlier_sigma, 12.0);
  EXPECT_EQ(d.theta_harmonic_order, 4);
  EXPECT_EQ(d.theta_harmonic_x, 0.03);
  EXPECT_EQ(d.theta_harmonic_y, 0.04);
  EXPECT_EQ(d.theta_harmonic_phase_rad, -1.0);
  EXPECT_EQ(d.bias_step_at, 0.25);
  EXPECT_EQ(d.bias_step_x, 0.05);
  EXPECT_EQ(d.bias_step_y, 0.06);
  EXPECT_EQ(d.scale_cubic_x, 1e-5);
  EXPECT_EQ(d.scale_cubic_y, -3e-5);
  const nlohmann::json truth =
      TruthJson(scenario, SimulateScenario(scenario, 1), 1)["disturbances"];
  EXPECT_EQ(truth["theta_harmonic_order"], 4);
  EXPECT_EQ(truth["scale_cubic_y"], -3e-5);
  EXPECT_EQ(truth.size(), DisturbanceNames().size() + 2);  // and the two index lists
}

TEST(Disturbances, BadValuesAreRefusedNamingTheKeyAndItsRange) {
  Scenario scenario;
  EXPECT_ERROR_CONTAINS(CourseScenarioWith(R"({"noise_ar2": [0.5, 0]})", &scenario),
                        "disturbances: unknown key \"noise_ar2\"");
  EXPECT_ERROR_CONTAINS(
      CourseScenarioWith(R"({"theta_harmonic": {"order": 2, "amplitude": [1, 0], "phse": 1}})",
                         &scenario),
      "disturbances.theta_harmonic: unknown key \"phse\"");
  EXPECT_ERROR_CONTAINS(CourseScenarioWith(R"({"noise_ar1": [1, 0]})", &scenario),
                        "noise_ar1_x = 1 is outside (-0.99, 0.99)");
  EXPECT_ERROR_CONTAINS(CourseScenarioWith(R"({"noise_ar1": 0.5})", &scenario),
                        "disturbances.noise_ar1 must be two finite numbers [x, y]");
  EXPECT_ERROR_CONTAINS(CourseScenarioWith(R"({"noise_student_t_dof": 2})", &scenario),
                        "noise_student_t_dof = 2 is outside (2, 1000]");
  EXPECT_ERROR_CONTAINS(CourseScenarioWith(R"({"outlier_fraction": 0.5})", &scenario),
                        "outlier_fraction = 0.5 is outside [0, 0.2]");
  EXPECT_ERROR_CONTAINS(
      CourseScenarioWith(R"({"theta_harmonic": {"order": 2.5, "amplitude": [1, 0]}})", &scenario),
      "theta_harmonic_order = 2.5 must be a whole number from 1 to 20");
  EXPECT_ERROR_CONTAINS(CourseScenarioWith(R"({"theta_harmonic": {"order": 2}})", &scenario),
                        "disturbances.theta_harmonic needs \"amplitude\"");
  EXPECT_ERROR_CONTAINS(
      CourseScenarioWith(R"({"bias_step": {"at": 1, "size": [1, 0]}})", &scenario),
      "bias_step_at = 1 is outside (0, 1)");
  // --set is held to the same ranges, and an unknown name lists the disturbances.
  const auto override_message = [](const std::string& assignments) {
    Scenario course;
    EXPECT_TRUE(CourseScenarioWith("", &course).ok());
    return ApplyScenarioOverrides(assignments, &course);
  };
  EXPECT_ERROR_CONTAINS(override_message("noise_ar1_y=-0.99"),
                        "noise_ar1_y = -0.99 is outside (-0.99, 0.99)");
  EXPECT_ERROR_CONTAINS(override_message("scale_cubic_x=1"),
                        "scale_cubic_x = 1 is outside [-0.01, 0.01] 1/(m/s^2)^2");
  EXPECT_ERROR_CONTAINS(override_message("theta_harmonic_order=21"),
                        "theta_harmonic_order = 21 must be a whole number from 1 to 20");
  EXPECT_ERROR_CONTAINS(override_message("noise_ar2=1"),
                        "nor a disturbance (noise_ar1_x, noise_ar1_y, noise_student_t_dof,");
}

}  // namespace
}  // namespace accelcal
