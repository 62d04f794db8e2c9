// The linear baseline: both solvers agree, the truth is recovered within the reported
// sigma, the reported sigma matches the Monte Carlo spread, and a design that cannot
// separate bias from scale is refused with a reason.

#include "estimation/tilt_table/linear_ls.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <vector>

#include "estimation/statistics/chi_square.h"
#include "estimation/tilt_table/ceres_linear_ls.h"
#include "models/tilt_table.h"
#include "simulation/random.h"
#include "simulation/simulator.h"
#include "test_support.h"

namespace accelcal {
namespace {

LinearLsOptions OptionsFor(const SimulationTruth& truth) {
  LinearLsOptions options;
  options.gravity_mps2 = truth.gravity_mps2;
  options.noise_variance_x = truth.stated_noise_variance_x;
  options.noise_variance_y = truth.stated_noise_variance_y;
  return options;
}

Eigen::Vector4d TruthVector(const SimulationTruth& truth) {
  const ModelParameters<double>& p = truth.parameters;
  return Eigen::Vector4d(p[Parameter::kBiasX], p[Parameter::kScaleX], p[Parameter::kBiasY],
                         p[Parameter::kScaleY]);
}

// Independent reference: the normal equations of one axis solved in long double
// (test_support.h).
Eigen::Vector2d BatchAxisSolution(const CalibrationTest& test, bool x_axis) {
  const testing::PlainAxisFit fit = testing::PlainBaselineFit(test, x_axis ? 0 : 1, 1.0);
  return Eigen::Vector2d(fit.bias, fit.scale);
}

TEST(LinearLs, ClosedFormAndCeresAgreeToOneInABillion) {
  const SimulationTruth truth = CourseTableOneTruth();
  for (const int samples : {50, 2001, 20001}) {
    for (const uint64_t seed : {1u, 2u, 3u}) {
      TiltSchedule design;
      design.sample_count = samples;
      const CalibrationTest test = SimulateTiltTest(design, truth, seed);
      BaselineFit closed_form;
      ASSERT_TRUE(EstimateLinearLs(test, OptionsFor(truth), &closed_form).ok());
      CeresLinearLsOptions ceres_options;
      ceres_options.model = OptionsFor(truth);
      CeresLinearLsResult ceres;
      const Status status = EstimateLinearLsWithCeres(test, ceres_options, &ceres);
      ASSERT_TRUE(status.ok()) << status.message();
      const FitDifference difference = CompareFits(closed_form, ceres.fit);
      EXPECT_LT(difference.parameters, 1e-9) << samples << " samples, seed " << seed;
      EXPECT_LT(difference.covariance, 1e-9) << samples << " samples, seed " << seed;
      EXPECT_NEAR(closed_form.chi2_x.chi2, ceres.fit.chi2_x.chi2, 1e-9 * closed_form.chi2_x.chi2);
      EXPECT_NEAR(closed_form.chi2_y.chi2, ceres.fit.chi2_y.chi2, 1e-9 * closed_form.chi2_y.chi2);
    }
  }
}

TEST(LinearLs, MatchesALongDoubleBatchSolutionOnANarrowOffCentreDesign) {
  // Angles in [1.0, 1.3] rad: the specific force has a large mean and a small spread,
  // where naive sums lose digits; the shifted sums must not.
  SimulationTruth truth = CourseTableOneTruth();
  TiltSchedule design;
  design.sample_count = 5000;
  design.theta_begin_rad = 1.0;
  design.theta_end_rad = 1.3;
  const CalibrationTest test = SimulateTiltTest(design, truth, 7);
  BaselineFit fit;
  ASSERT_TRUE(EstimateLinearLs(test, OptionsFor(truth), &fit).ok());
  const Eigen::Vector2d x = BatchAxisSolution(test, true);
  const Eigen::Vector2d y = BatchAxisSolution(test, false);
  EXPECT_NEAR(fit.parameters[BaselineIndex(Parameter::kBiasX)], x[0],
              1e-10 * std::abs(x[0]) + 1e-13);
  EXPECT_NEAR(fit.parameters[BaselineIndex(Parameter::kScaleX)], x[1],
              1e-10 * std::abs(x[1]) + 1e-13);
  EXPECT_NEAR(fit.parameters[BaselineIndex(Parameter::kBiasY)], y[0],
              1e-9 * std::abs(y[0]) + 1e-12);
  EXPECT_NEAR(fit.parameters[BaselineIndex(Parameter::kScaleY)], y[1],
              1e-9 * std::abs(y[1]) + 1e-12);
}

TEST(CalibrationAccumulator, MergedChunksEqualOnePass) {
  const SimulationTruth truth = CourseTableOneTruth();
  const CalibrationTest test = SimulateTiltTest(TiltSchedule(), truth, 11);
  CalibrationAccumulator whole(9.8);
  whole.AddTest(test);
  AxisRegressionAccumulator first;
  AxisRegressionAccumulator second;
  for (int i = 0; i < test.size(); ++i) {
    double fx;
    double fy;
    TiltTableSpecificForce(test.theta_rad[i], 9.8, &fx, &fy);
    (i < 700 ? first : second).Add(fx, test.measured_x[i] - fx);
  }
  first.Merge(second);
  EXPECT_EQ(first.count(), whole.x().count());
  EXPECT_NEAR(first.MeanForce(), whole.x().MeanForce(), 1e-12);
  EXPECT_NEAR(first.CenteredForceForce(), whole.x().CenteredForceForce(),
              1e-11 * whole.x().CenteredForceForce());
  EXPECT_NEAR(
      first.CenteredForceResponse(), whole.x().CenteredForceResponse(),
      1e-11 * std::sqrt(whole.x().CenteredForceForce() * whole.x().CenteredResponseResponse()));
  EXPECT_NEAR(first.CenteredResponseResponse(), whole.x().CenteredResponseResponse(),
              1e-11 * whole.x().CenteredResponseResponse());
}

// A test long enough for several threads: the course's table turned over and over, with
// noise, and a length that is not a multiple of the block.
CalibrationTest LongTiltTest() {
  const int size = 3 * CalibrationAccumulator::kParallelMinSamples + 1234;
  CalibrationTest test;
  RandomSource random(5);
  for (int i = 0; i < size; ++i) {
    const double theta = 0.3 + 40.0 * M_PI * i / size;  // 20 turns
    double fx;
    double fy;
    TiltTableSpecificForce(theta, 9.8, &fx, &fy);
    test.theta_rad.push_back(theta);
    test.measured_x.push_back(0.07 + (1 - 0.03) * fx + 0.5 * random.StandardNormal());
    test.measured_y.push_back(-0.02 + (1 + 0.01) * fy + 0.8 * random.StandardNormal());
  }
  return test;
}

void ExpectSameStatistics(const AxisRegressionAccumulator& a, const AxisRegressionAccumulator& b) {
  EXPECT_EQ(a.count(), b.count());
  EXPECT_NEAR(a.MeanForce(), b.MeanForce(), 1e-12);
  EXPECT_NEAR(a.MeanResponse(), b.MeanResponse(), 1e-12);
  EXPECT_NEAR(a.CenteredForceForce(), b.CenteredForceForce(), 1e-12 * b.CenteredForceForce());
  EXPECT_NEAR(a.CenteredForceResponse(), b.CenteredForceResponse(),
              1e-12 * std::sqrt(b.CenteredForceForce() * b.CenteredResponseResponse()));
  EXPECT_NEAR(a.CenteredResponseResponse(), b.CenteredResponseResponse(),
              1e-12 * b.CenteredResponseResponse());
}

TEST(CalibrationAccumulator, ThreadedPassEqualsOnePassAndRepeatsBitForBit) {
  const CalibrationTest test = LongTiltTest();
  CalibrationAccumulator serial(9.8);
  serial.AddTest(test);
  for (const int threads : {2, 3, 7}) {
    SCOPED_TRACE(threads);
    CalibrationAccumulator threaded(9.8);
    threaded.AddTest(test, threads);
    ExpectSameStatistics(threaded.x(), serial.x());
    ExpectSameStatistics(threaded.y(), serial.y());
    EXPECT_EQ(threaded.theta_min_rad(), serial.theta_min_rad());
    EXPECT_EQ(threaded.theta_max_rad(), serial.theta_max_rad());
    CalibrationAccumulator again(9.8);
    again.AddTest(test, threads);
    EXPECT_EQ(again.x().CenteredForceResponse(), threaded.x().CenteredForceResponse());
    EXPECT_EQ(again.y().CenteredResponseResponse(), threaded.y().CenteredResponseResponse());
    // The same bit for bit whatever the number of threads.
    CalibrationAccumulator one_thread(9.8);
    one_thread.AddTest(test, 1);
    EXPECT_EQ(one_thread.x().CenteredForceResponse(), threaded.x().CenteredForceResponse());
    EXPECT_EQ(one_thread.y().CenteredResponseResponse(), threaded.y().CenteredResponseResponse());
    EXPECT_EQ(one_thread.x().MeanResponse(), threaded.x().MeanResponse());
  }
  // Too short to split: the one-thread pass, bit for bit.
  CalibrationTest short_test = test;
  short_test.theta_rad.resize(CalibrationAccumulator::kParallelMinSamples + 7);
  short_test.measured_x.resize(short_test.theta_rad.size());
  short_test.measured_y.resize(short_test.theta_rad.size());
  CalibrationAccumulator one(9.8);
  one.AddTest(short_test);
  CalibrationAccumulator asked_for_two(9.8);
  asked_for_two.AddTest(short_test, 2);
  EXPECT_EQ(asked_for_two.x().CenteredForceForce(), one.x().CenteredForceForce());
  EXPECT_EQ(asked_for_two.y().MeanResponse(), one.y().MeanResponse());
}

TEST(CalibrationAccumulator, MergeTakesTheAngleSpanAndIgnoresAnEmptySide) {
  const CalibrationTest test = LongTiltTest();
  CalibrationTest first;
  CalibrationTest second;
  for (int i = 0; i < 5000; ++i) {
    CalibrationTest& part = i < 2000 ? first : second;
    part.theta_rad.push_back(test.theta_rad[i]);
    part.measured_x.push_back(test.measured_x[i]);
    part.measured_y.push_back(test.measured_y[i]);
  }
  CalibrationAccumulator a(9.8);
  a.AddTest(second);
  CalibrationAccumulator b(9.8);
  b.AddTest(first);
  CalibrationAccumulator empty(9.8);
  a.Merge(empty);
  empty.Merge(b);
  empty.Merge(a);  // first, then second, as one test
  EXPECT_EQ(empty.theta_min_rad(), test.theta_rad[0]);
  EXPECT_EQ(empty.theta_max_rad(), test.theta_rad[4999]);
  CalibrationAccumulator whole(9.8);
  for (int i = 0; i < 5000; ++i)
    whole.Add(test.theta_rad[i], test.measured_x[i], test.measured_y[i]);
  ExpectSameStatistics(empty.x(), whole.x());
  ExpectSameStatistics(empty.y(), whole.y());
}

TEST(LinearLs, RecoversTheTruthWithinThreeSigma) {
  const SimulationTruth truth = CourseTableOneTruth();
  TiltSchedule design;
  design.sample_count = 20001;
  const CalibrationTest test = SimulateTiltTest(design, truth, 42);
  BaselineFit fit;
  ASSERT_TRUE(EstimateLinearLs(test, OptionsFor(truth), &fit).ok());
  const Eigen::Vector4d z =
      (fit.parameters - TruthVector(truth)).cwiseQuotient(fit.StandardDeviations());
  EXPECT_LT(z.cwiseAbs().maxCoeff(), 3.0) << z.transpose();
}

// Reported sigma against the Monte Carlo spread, and 95% interval coverage, over 2000
// independent tests. The standard deviation of an estimated sigma from K trials is about
// sigma / sqrt(2K) = 1.6%; the tolerance of 7% is over 4 of those. The coverage of a
// nominal 95% interval has a binomial sd of 0.49%; the tolerance is 2%.
TEST(LinearLs, ReportedSigmaMatchesMonteCarloSpreadAndCovers95Percent) {
  const SimulationTruth truth = CourseTableOneTruth();
  TiltSchedule design;
  design.sample_count = 200;
  design.theta_begin_rad = 0.2;  // an asymmetric design, so bias and scale correlate
  design.theta_end_rad = 4.0;
  const int trials = 2000;
  std::vector<Eigen::Vector4d> estimates;
  Eigen::Matrix4d reported = Eigen::Matrix4d::Zero();
  Eigen::Vector4i covered = Eigen::Vector4i::Zero();
  for (int trial = 0; trial < trials; ++trial) {
    const CalibrationTest test = SimulateTiltTest(design, truth, 2024, trial);
    BaselineFit fit;
    ASSERT_TRUE(EstimateLinearLs(test, OptionsFor(truth), &fit).ok());
    estimates.push_back(fit.parameters);
    reported = fit.covariance;  // the same design every trial: the same covariance
    for (int i = 0; i < 4; ++i) {
      covered[i] += std::abs(fit.parameters[i] - TruthVector(truth)[i]) <=
                    1.959963984540054 * std::sqrt(fit.covariance(i, i));
    }
  }
  Eigen::Vector4d mean = Eigen::Vector4d::Zero();
  for (const auto& estimate : estimates) mean += estimate / trials;
  Eigen::Matrix4d empirical = Eigen::Matrix4d::Zero();
  for (const auto& estimate : estimates) {
    empirical += (estimate - mean) * (estimate - mean).transpose() / (trials - 1);
  }
  for (int i = 0; i < 4; ++i) {
    const double ratio = std::sqrt(empirical(i, i) / reported(i, i));
    std::printf("%-8s empirical/reported sigma %.3f, 95%% interval coverage %.2f%%\n",
                Info(kBaselineParameters[i]).name, ratio, 100.0 * covered[i] / trials);
    EXPECT_NEAR(ratio, 1.0, 0.07) << Info(kBaselineParameters[i]).name;
    EXPECT_NEAR(covered[i] / static_cast<double>(trials), 0.95, 0.02)
        << Info(kBaselineParameters[i]).name;
  }
  // The bias/scale correlation of each axis is reproduced too (sd ~ 0.02 for K = 2000).
  const double reported_rho = reported(0, 1) / std::sqrt(reported(0, 0) * reported(1, 1));
  const double empirical_rho = empirical(0, 1) / std::sqrt(empirical(0, 0) * empirical(1, 1));
  EXPECT_GT(std::abs(reported_rho), 0.3);
  EXPECT_NEAR(empirical_rho, reported_rho, 0.07);
}

TEST(LinearLs, ChiSquareFollowsItsDistributionUnderTheStatedNoise) {
  const SimulationTruth truth = CourseTableOneTruth();
  TiltSchedule design;
  design.sample_count = 500;
  const int trials = 1000;
  double sum = 0.0;
  int rejected = 0;
  for (int trial = 0; trial < trials; ++trial) {
    BaselineFit fit;
    ASSERT_TRUE(
        EstimateLinearLs(SimulateTiltTest(design, truth, 99, trial), OptionsFor(truth), &fit).ok());
    sum += fit.chi2_x.chi2 / fit.chi2_x.dof;
    rejected += fit.chi2_x.p_value < 0.05;
  }
  // mean chi2/dof is 1 with sd sqrt(2/dof/trials) = 0.002; the 5% test rejects 5% +- 0.7%.
  EXPECT_NEAR(sum / trials, 1.0, 0.01);
  EXPECT_NEAR(rejected / static_cast<double>(trials), 0.05, 0.022);
}

TEST(LinearLs, WrongStatedVarianceShowsInChiSquare) {
  SimulationTruth truth = CourseTableOneTruth();
  truth.parameters[Parameter::kNoiseVarianceX] = 2.0;  // twice the stated variance
  const CalibrationTest test = SimulateTiltTest(TiltSchedule(), truth, 5);
  LinearLsOptions options = OptionsFor(truth);
  BaselineFit fit;
  ASSERT_TRUE(EstimateLinearLs(test, options, &fit).ok());
  EXPECT_NEAR(fit.chi2_x.chi2 / fit.chi2_x.dof, 2.0, 0.15);
  EXPECT_LT(fit.chi2_x.p_value, 1e-10);
  EXPECT_GT(fit.chi2_y.p_value, 1e-4);
}

TEST(LinearLs, RefusesATestThatSpansTooLittleToSeparateBiasFromScale) {
  TiltSchedule design;
  design.sample_count = 1000;
  design.theta_begin_rad = 0.0;
  design.theta_end_rad = 0.02;
  const CalibrationTest test = SimulateTiltTest(design, CourseTableOneTruth(), 3);
  BaselineFit fit;
  const Status status = EstimateLinearLs(test, OptionsFor(CourseTableOneTruth()), &fit);
  ASSERT_FALSE(status.ok());
  // Over 0.02 rad the x axis' force hardly varies (sin theta < 0.02): its scale is unknown.
  EXPECT_NE(status.message().find("(theta from 0 to 0.02 rad), so scale_x could not be known"),
            std::string::npos)
      << status.message();
  // The Ceres path gives the same message rather than a rank-deficiency failure.
  CeresLinearLsOptions ceres_options;
  ceres_options.model = OptionsFor(CourseTableOneTruth());
  CeresLinearLsResult ceres;
  EXPECT_EQ(EstimateLinearLsWithCeres(test, ceres_options, &ceres).message(), status.message());
}

TEST(LinearLs, RefusesASingleAngleAndTooFewSamples) {
  CalibrationTest test;
  test.theta_rad = {0.5, 0.5, 0.5, 0.5};
  test.measured_x = {1, 2, 3, 4};
  test.measured_y = {1, 2, 3, 4};
  BaselineFit fit;
  Status status = EstimateLinearLs(test, OptionsFor(CourseTableOneTruth()), &fit);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("theta spans 0 rad"), std::string::npos) << status.message();
  test.theta_rad.resize(2);
  test.measured_x.resize(2);
  test.measured_y.resize(2);
  status = EstimateLinearLs(test, OptionsFor(CourseTableOneTruth()), &fit);
  EXPECT_NE(status.message().find("at least 3"), std::string::npos) << status.message();
}

TEST(LinearLs, RefusesNonPositiveVariances) {
  const CalibrationTest test = SimulateTiltTest(TiltSchedule(), CourseTableOneTruth(), 3);
  LinearLsOptions options = OptionsFor(CourseTableOneTruth());
  options.noise_variance_y = 0.0;
  BaselineFit fit;
  const Status status = EstimateLinearLs(test, options, &fit);
  EXPECT_NE(status.message().find("noise_variance_y must be a positive"), std::string::npos)
      << status.message();
}

// scipy.stats.f.sf at the same points (SciPy 1.10, Debian 12).
TEST(FDistribution, MatchesScipy) {
  EXPECT_NEAR(FSurvival(4.2, 1, 29), 0.049565574255366424, 1e-12);
  EXPECT_NEAR(FSurvival(0.3, 1, 5), 0.6074354940759237, 1e-12);
  EXPECT_NEAR(FSurvival(30, 1, 26) / 9.58138518856829e-06, 1.0, 1e-9);
  EXPECT_NEAR(FSurvival(2.5, 3, 40), 0.07325435201794978, 1e-12);
  EXPECT_NEAR(FSurvival(100, 1, 10) / 1.5895531755964125e-06, 1.0, 1e-9);
  EXPECT_EQ(FSurvival(0.0, 1, 10), 1.0);
}

TEST(ChiSquare, MatchesClosedFormsAndTables) {
  // dof 2: survival is exp(-x/2) exactly.
  for (const double x : {0.1, 1.0, 5.0, 40.0}) {
    EXPECT_NEAR(ChiSquareSurvival(x, 2.0), std::exp(-x / 2),
                1e-14 * std::max(1.0, std::exp(-x / 2)));
  }
  EXPECT_NEAR(ChiSquareSurvival(200.0, 2.0) / std::exp(-100.0), 1.0, 1e-12);
  // 95% quantiles from tables.
  EXPECT_NEAR(ChiSquareCdf(3.841458820694124, 1), 0.95, 1e-12);
  EXPECT_NEAR(ChiSquareCdf(18.307038053275146, 10), 0.95, 1e-12);
  // Large dof: the distribution is close to N(dof, 2 dof); the median is near dof - 2/3.
  EXPECT_NEAR(ChiSquareCdf(19999.0 - 2.0 / 3.0, 19999), 0.5, 1e-3);
  EXPECT_NEAR(ChiSquareCdf(19999.0 + 2.0 * 200.0, 19999), 0.97725, 2e-3);
  EXPECT_NEAR(ChiSquareTwoSidedPValue(19999.0 - 2.0 / 3.0, 19999), 1.0, 2e-3);
}

}  // namespace
}  // namespace accelcal
