// How many samples: the wrong-landmark probability against brute-force sampling, the
// design covariance against the estimator's own, N_min monotone in the criterion, the
// analytic curve against a full-simulation Monte Carlo, the binary's N_min and Monte Carlo
// checks against independent computations and exact binomial tests, and the evenly spaced
// subsets of the real test against the analytic spread.

#include "studies/min_samples.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "estimation/tilt_table/landmark_decision.h"
#include "estimation/tilt_table/linear_ls.h"
#include "estimation/tilt_table/trajectory.h"
#include "io/course_data.h"
#include "io/scenario_json.h"
#include "models/tilt_table.h"
#include "simulation/monte_carlo.h"
#include "simulation/random.h"
#include "test_support.h"

namespace accelcal {
namespace {

TEST(ProbabilityOfWrongLandmark, MatchesBruteForceSampling) {
  const std::vector<Landmark> landmarks = {
      {"A", 0, 0}, {"B", 30, 5}, {"C", -10, 25}, {"D", 5, -40}};
  Eigen::Matrix2d decision;
  decision << 120.0, 30.0, 30.0, 200.0;
  Eigen::Matrix2d spread;
  spread << 90.0, -10.0, -10.0, 160.0;
  const Eigen::Vector2d center(2.0, -1.0);
  const double analytic = ProbabilityOfWrongLandmark(center, spread, decision, landmarks, 0);
  const Eigen::Matrix2d root = spread.llt().matrixL();
  const Eigen::Matrix2d metric = decision.inverse();
  RandomSource random(17);
  const int samples = 400000;
  int wrong = 0;
  for (int s = 0; s < samples; ++s) {
    const Eigen::Vector2d p =
        center + root * Eigen::Vector2d(random.StandardNormal(), random.StandardNormal());
    int best = 0;
    double best_d = HUGE_VAL;
    for (size_t k = 0; k < landmarks.size(); ++k) {
      const Eigen::Vector2d d = p - Eigen::Vector2d(landmarks[k].x_m, landmarks[k].y_m);
      if (d.dot(metric * d) < best_d) {
        best_d = d.dot(metric * d);
        best = static_cast<int>(k);
      }
    }
    wrong += best != 0;
  }
  const double rate = wrong / static_cast<double>(samples);
  EXPECT_GT(analytic, 0.05);  // a case where the answer is not trivially 0 or 1
  EXPECT_NEAR(analytic, rate, 4 * std::sqrt(rate * (1 - rate) / samples));
}

// Hundreds of landmarks around the truth, most of them hidden behind nearer ones: the cell is
// bounded by a few of them only (the others are pruned), and the answer must still be the
// sampled rate of wrong decisions over all of them.
TEST(ProbabilityOfWrongLandmark, ManyLandmarksMatchBruteForceSampling) {
  RandomSource placement(5);
  std::vector<Landmark> landmarks = {{"T", 0, 0}};
  for (int k = 0; k < 400; ++k) {
    const double x = 200.0 * (placement.Uniform() - 0.5);
    const double y = 200.0 * (placement.Uniform() - 0.5);
    if (std::hypot(x, y) > 12.0) landmarks.push_back({"L" + std::to_string(k), x, y});
  }
  Eigen::Matrix2d covariance;
  covariance << 60.0, 15.0, 15.0, 90.0;
  const Eigen::Vector2d center(1.0, -2.0);
  const double analytic = ProbabilityOfWrongLandmark(center, covariance, covariance, landmarks, 0);
  const Eigen::Matrix2d root = covariance.llt().matrixL();
  const Eigen::Matrix2d metric = covariance.inverse();
  RandomSource random(23);
  const int samples = 100000;
  int wrong = 0;
  for (int s = 0; s < samples; ++s) {
    const Eigen::Vector2d p =
        center + root * Eigen::Vector2d(random.StandardNormal(), random.StandardNormal());
    const double truth_d = p.dot(metric * p);
    for (size_t k = 1; k < landmarks.size(); ++k) {
      const Eigen::Vector2d d = p - Eigen::Vector2d(landmarks[k].x_m, landmarks[k].y_m);
      if (d.dot(metric * d) < truth_d) {
        ++wrong;
        break;
      }
    }
  }
  const double rate = wrong / static_cast<double>(samples);
  EXPECT_GT(analytic, 0.05);
  EXPECT_LT(analytic, 0.95);
  EXPECT_NEAR(analytic, rate, 4 * std::sqrt(rate * (1 - rate) / samples) + 2e-3);
}

TEST(BaselineCovarianceForDesign, IsTheEstimatorsOwnCovariance) {
  for (const char* design : {"uniform", "four", "two"}) {
    const std::vector<double> angles = DesignAngles(design, 400);
    TiltSchedule schedule;
    schedule.kind = TiltSchedule::Kind::kList;
    schedule.angles_rad = angles;
    const CalibrationTest test = SimulateTiltTest(schedule, CourseTableOneTruth(), 3);
    LinearLsOptions options;
    options.noise_variance_x = 0.25;
    options.noise_variance_y = 0.64;
    BaselineFit fit;
    ASSERT_TRUE(EstimateLinearLs(test, options, &fit).ok()) << design;
    EXPECT_EIGEN_NEAR(BaselineCovarianceForDesign(angles, 9.8, 0.25, 0.64), fit.covariance, 1e-15);
  }
}

struct CourseLikeModel {
  EndpointModel model;
  SimulatedData reference;
  int truth = 0;
  Scenario scenario;
};

CourseLikeModel MakeModel() {
  CourseLikeModel c;
  EXPECT_TRUE(LoadDefaultScenario(&c.scenario).ok());
  c.reference = SimulateScenario(c.scenario, 5);
  LinearLsOptions options;
  options.noise_variance_x = 0.25;
  options.noise_variance_y = 0.64;
  BaselineFit fit;
  EXPECT_TRUE(EstimateLinearLs(c.reference.test, options, &fit).ok());
  TrajectoryOptions trajectory_options;
  trajectory_options.path_stride = c.reference.run.size();
  DeadReckoningResult trajectory;
  EXPECT_TRUE(
      DeadReckon(c.reference.run, c.reference.conditions, fit, trajectory_options, &trajectory)
          .ok());
  c.model.jacobian = trajectory.jacobian;
  c.model.noise_part = trajectory.noise_part;
  c.model.endpoint = trajectory.endpoint;
  c.model.noise_variance_x = 0.25;
  c.model.noise_variance_y = 0.64;
  for (size_t k = 0; k < c.reference.landmarks.size(); ++k) {
    if (c.reference.landmarks[k].name == c.reference.reached_landmark)
      c.truth = static_cast<int>(k);
  }
  return c;
}

TEST(AnalyseDesign, NMinGrowsAsTheCriterionTightens) {
  const CourseLikeModel c = MakeModel();
  DesignCurve design;
  design.name = "uniform";
  int previous = 0;
  for (const double max_error : {0.05, 0.02, 0.01, 0.005, 0.002}) {
    const DesignCurve result =
        AnalyseDesign(c.model, c.reference.landmarks, c.truth, design, max_error, 20001);
    ASSERT_GT(result.n_min, 0) << max_error;
    EXPECT_GT(result.n_min, previous) << max_error;
    // N_min is the smallest: one sample fewer misses the criterion.
    EXPECT_LE(EvaluateDesign(c.model, c.reference.landmarks, c.truth, design, result.n_min).p_wrong,
              max_error);
    EXPECT_GT(
        EvaluateDesign(c.model, c.reference.landmarks, c.truth, design, result.n_min - 1).p_wrong,
        max_error);
    previous = result.n_min;
  }
  // Below the run's noise floor no N suffices.
  EXPECT_EQ(AnalyseDesign(c.model, c.reference.landmarks, c.truth, design, 1e-5, 20001).n_min, -1);
}

// The analytic P(wrong) at N = 1000 (about 0.1 here) against 1500 full simulations of
// test and run: within 4 binomial sd.
TEST(AnalyseDesign, AnalyticCurveAgreesWithFullSimulation) {
  const CourseLikeModel c = MakeModel();
  DesignCurve design;
  design.name = "uniform";
  const int n = 1000;
  const double analytic =
      EvaluateDesign(c.model, c.reference.landmarks, c.truth, design, n).p_wrong;
  TiltSchedule schedule;
  schedule.kind = TiltSchedule::Kind::kList;
  schedule.angles_rad = DesignAngles("uniform", n);
  std::vector<double> t;
  std::vector<double> ax;
  std::vector<double> ay;
  TrueRunAcceleration(c.scenario.run, &t, &ax, &ay);
  const int trials = 1500;
  std::vector<int> wrong(trials, 0);
  MonteCarloOptions monte_carlo;
  monte_carlo.trials = trials;
  RunTrials(monte_carlo, [&](int trial) {
    const CalibrationTest test = SimulateTiltTest(schedule, c.scenario.truth, 99, trial);
    const VehicleRun run = SimulateVehicleRun(t, ax, ay, c.scenario.truth, 99, trial);
    LinearLsOptions options;
    options.noise_variance_x = 0.25;
    options.noise_variance_y = 0.64;
    BaselineFit fit;
    TrajectoryOptions trajectory_options;
    trajectory_options.path_stride = run.size();
    DeadReckoningResult trajectory;
    if (!EstimateLinearLs(test, options, &fit).ok() ||
        !DeadReckon(run, c.reference.conditions, fit, trajectory_options, &trajectory).ok()) {
      wrong[trial] = 1;
      return;
    }
    wrong[trial] =
        DecideLandmark(trajectory.endpoint, trajectory.covariance, c.reference.landmarks, 0.01)
            .best != c.truth;
  });
  const double rate = std::count(wrong.begin(), wrong.end(), 1) / static_cast<double>(trials);
  std::printf("N = %d: P(wrong) analytic %.4f, Monte Carlo %.4f (%d trials)\n", n, analytic, rate,
              trials);
  EXPECT_GT(analytic, 0.03);
  EXPECT_NEAR(rate, analytic, 4 * std::sqrt(analytic * (1 - analytic) / trials));
}

// Two-sided exact binomial p-value of `count` successes in `trials` at probability p:
// 2 min(P(X <= count), P(X >= count)), capped at 1.
double BinomialTwoSidedPValue(int count, int trials, double p) {
  p = std::min(std::max(p, 1e-300), 1.0 - 1e-16);
  double lower = 0.0;
  double upper = 0.0;
  for (int k = 0; k <= trials; ++k) {
    const double log_pmf = std::lgamma(trials + 1.0) - std::lgamma(k + 1.0) -
                           std::lgamma(trials - k + 1.0) + k * std::log(p) +
                           (trials - k) * std::log1p(-p);
    const double pmf = std::exp(log_pmf);
    if (k <= count) lower += pmf;
    if (k >= count) upper += pmf;
  }
  return std::min(1.0, 2.0 * std::min(lower, upper));
}

// The course data, its full-data baseline fit and the endpoint model, computed here from
// the library's estimator and dead reckoning (not from studies/min_samples).
struct CourseModel {
  CourseData data;
  BaselineFit fit;
  DeadReckoningResult trajectory;
  int truth = -1;  // index of C, the full-data decision
};

bool LoadCourseModel(const std::string& dir, CourseModel* c) {
  DataFiles files;
  if (!ResolveDataFiles(dir, &files).ok() || !LoadDataFiles(files, &c->data).ok()) return false;
  LinearLsOptions options = LinearLsOptionsFor(c->data.conditions, kCourseGravityMps2);
  TrajectoryOptions trajectory_options;
  trajectory_options.path_stride = c->data.run.size();
  if (!EstimateLinearLs(c->data.test, options, &c->fit).ok() ||
      !DeadReckon(c->data.run, c->data.conditions, c->fit, trajectory_options, &c->trajectory)
           .ok()) {
    return false;
  }
  for (size_t k = 0; k < c->data.landmarks.size(); ++k)
    if (c->data.landmarks[k].name == "C") c->truth = static_cast<int>(k);
  return c->truth >= 0;
}

// The endpoint covariance of an N-sample uniform sweep, written out here: per axis the
// baseline's sigma^2 (A^T A)^-1 with rows (1, f_i), f = -g sin(theta_i) for x and
// -g cos(theta_i) for y, theta_i = 2 pi i / (N - 1), through the endpoint's Jacobian, plus
// the run's own noise part.
Eigen::Matrix2d UniformSweepEndpointCovariance(const CourseModel& c, int samples) {
  Eigen::Matrix4d parameters = Eigen::Matrix4d::Zero();
  for (int axis = 0; axis < 2; ++axis) {
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    for (int i = 0; i < samples; ++i) {
      const double theta = 2.0 * M_PI * i / (samples - 1);
      const double f = axis == 0 ? -9.8 * std::sin(theta) : -9.8 * std::cos(theta);
      normal(0, 0) += 1.0;
      normal(0, 1) += f;
      normal(1, 1) += f * f;
    }
    normal(1, 0) = normal(0, 1);
    const double variance =
        axis == 0 ? c.data.conditions.noise_variance_x : c.data.conditions.noise_variance_y;
    parameters.block<2, 2>(2 * axis, 2 * axis) = variance * normal.inverse();
  }
  return c.trajectory.jacobian * parameters * c.trajectory.jacobian.transpose() +
         c.trajectory.noise_part;
}

// P(a wrong landmark) by sampling the endpoint ~ N(C, covariance) and deciding the landmark
// at the smallest Mahalanobis distance (no quadrature, no cell geometry).
double SampledWrongRate(const CourseModel& c, const Eigen::Matrix2d& covariance, int draws,
                        uint64_t seed) {
  const Eigen::Matrix2d root = covariance.llt().matrixL();
  const Eigen::Matrix2d metric = covariance.inverse();
  const std::vector<Landmark>& landmarks = c.data.landmarks;
  const Eigen::Vector2d truth(landmarks[c.truth].x_m, landmarks[c.truth].y_m);
  RandomSource random(seed);
  int wrong = 0;
  for (int s = 0; s < draws; ++s) {
    const Eigen::Vector2d p =
        truth + root * Eigen::Vector2d(random.StandardNormal(), random.StandardNormal());
    const double truth_distance = (p - truth).dot(metric * (p - truth));
    for (size_t k = 0; k < landmarks.size(); ++k) {
      const Eigen::Vector2d d = p - Eigen::Vector2d(landmarks[k].x_m, landmarks[k].y_m);
      if (static_cast<int>(k) != c.truth && d.dot(metric * d) < truth_distance) {
        ++wrong;
        break;
      }
    }
  }
  return wrong / static_cast<double>(draws);
}

// The binary's answers on the course data against an independent computation: N_min (the
// fewest samples with P(wrong) <= 0.01) checked by sampling the endpoint at 0.9 and 1.0
// N_min, N_min_3sigma (the fewest with one landmark in the 3-sigma ellipse) exactly from the
// written-out covariance, and the report's per-axis gaps from the landmarks themselves.
TEST(MinSamplesBinary, AnswersTheReportsQuestionOnTheCourseData) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  CourseModel c;
  ASSERT_TRUE(LoadCourseModel(dir, &c));
  testing::ScratchDir out;
  const testing::CommandResult result = testing::RunBinary(
      "min_samples",
      "--data_dir='" + dir + "' --design=all --repetitions=0 --json='" + out.File("m.json") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  // The report's own per-axis gaps: the smallest coordinate difference between C and another
  // landmark, per axis.
  const Landmark& truth = c.data.landmarks[c.truth];
  double gap[2] = {HUGE_VAL, HUGE_VAL};
  std::string nearest[2];
  for (const Landmark& other : c.data.landmarks) {
    if (other.name == truth.name) continue;
    const double d[2] = {std::abs(other.x_m - truth.x_m), std::abs(other.y_m - truth.y_m)};
    for (int axis = 0; axis < 2; ++axis) {
      if (d[axis] < gap[axis]) gap[axis] = d[axis], nearest[axis] = other.name;
    }
  }
  char expected[160];
  std::snprintf(expected, sizeof(expected),
                "d_min,x = %.2f m\n  (C-%s) and d_min,y = %.2f m (C-%s)", gap[0],
                nearest[0].c_str(), gap[1], nearest[1].c_str());
  EXPECT_NE(result.stdout_text.find(expected), std::string::npos)
      << "expected: " << expected << "\n"
      << result.stdout_text;

  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("m.json")));
  EXPECT_EQ(json["truth"], "C");
  ASSERT_EQ(json["designs"].size(), 4u);
  ASSERT_EQ(json["designs"][0]["name"], "uniform");
  const int n_min = json["designs"][0]["n_min"].get<int>();
  const int n_min_3sigma = json["designs"][0]["n_min_3sigma"].get<int>();
  ASSERT_GT(n_min, 100);
  ASSERT_GT(n_min_3sigma, 10);
  // 10^6 draws: the sampled rate's sd is 1e-4 near 0.01. P(wrong) falls by about 20% per 10%
  // more samples here (0.0122 at 0.9 N_min), so both bounds hold by more than 10 sd; at
  // 4 sd the false-failure rate is 6e-5 per bound.
  const int draws = 1000000;
  const double sd = std::sqrt(0.01 * 0.99 / draws);
  EXPECT_LE(SampledWrongRate(c, UniformSweepEndpointCovariance(c, n_min), draws, 31), 0.01 + 4 * sd)
      << "N_min = " << n_min;
  EXPECT_GT(SampledWrongRate(c, UniformSweepEndpointCovariance(c, n_min * 9 / 10), draws, 32),
            0.01 + 4 * sd)
      << "0.9 N_min = " << n_min * 9 / 10 << " should not meet the criterion";
  // The 3-sigma ellipse around the full-data endpoint: exact, no sampling.
  auto landmarks_in_3sigma = [&](int samples) {
    const Eigen::Matrix2d inverse = UniformSweepEndpointCovariance(c, samples).inverse();
    int inside = 0;
    for (const Landmark& landmark : c.data.landmarks) {
      const Eigen::Vector2d d = Eigen::Vector2d(landmark.x_m, landmark.y_m) - c.trajectory.endpoint;
      inside += d.dot(inverse * d) <= 9.0;
    }
    return inside;
  };
  EXPECT_EQ(landmarks_in_3sigma(n_min_3sigma), 1) << n_min_3sigma;
  EXPECT_GT(landmarks_in_3sigma(n_min_3sigma - 1), 1) << n_min_3sigma - 1;
  for (const auto& design : json["designs"]) {
    // Every balanced design needs about the same N: the bias dominates the parameter
    // part, and no design estimates a bias better than sigma^2 / N.
    EXPECT_NEAR(design["n_min"].get<int>(), n_min, 5) << design["name"];
    EXPECT_NEAR(design["n_min_3sigma"].get<int>(), n_min_3sigma, 5) << design["name"];
  }
  testing::ExpectBadInputContract(testing::RunBinary("min_samples", "--design=six"), "min_samples",
                                  "--design must be uniform, four, two, optimal or all");
}

// The binary's Monte Carlo checks against its analytic P(wrong), each by an exact binomial
// test: full simulations of test and run, and random subsets of the real test, 1500 each, at
// N_min / 4 (P about 0.11 and 0.04: far from 0, so the comparison has power: the binomial sd
// is 0.008 at 0.11, so a 30% error in P is 4 sd) and at N_min (P 0.0099: 15 expected, a
// factor 2 is 4 sd). Each of the four checks fails falsely with probability 1e-4. (The old
// tolerance, 4 sd + 0.01 at 200 runs, passed with the run's noise dropped from the model.) Evenly
// spaced subsets of the real test are left out here: there are only full/N of them (18 at N_min /
// 4), so their rate cannot test a P of 0.04 (0 of 18 happens with probability 0.48); the next test
// checks them by their spread instead.
TEST(MinSamplesBinary, MonteCarloChecksAgreeWithTheAnalyticCurveWithinBinomialError) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  testing::ScratchDir out;
  const int repetitions = 1500;
  const testing::CommandResult result = testing::RunBinary(
      "min_samples", "--data_dir='" + dir + "' --design=uniform --repetitions=" +
                         std::to_string(repetitions) + " --json='" + out.File("m.json") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("m.json")));
  ASSERT_EQ(json["designs"].size(), 1u);
  int checked = 0;
  double largest_analytic = 0.0;
  for (const auto& check : json["designs"][0]["monte_carlo"]) {
    const std::string kind = check["kind"];
    if (kind == "real_test_even_subsets") continue;
    ASSERT_EQ(check["repetitions"].get<int>(), repetitions);
    const double analytic = check["analytic"].get<double>();
    const int count =
        static_cast<int>(std::lround(check["monte_carlo"].get<double>() * repetitions));
    const double p_value = BinomialTwoSidedPValue(count, repetitions, analytic);
    std::printf("%s N = %d: analytic %.4f, Monte Carlo %d/%d, binomial p %.3g\n", kind.c_str(),
                check["n"].get<int>(), analytic, count, repetitions, p_value);
    EXPECT_GE(p_value, 1e-4) << kind << " N = " << check["n"] << ": analytic " << analytic
                             << ", Monte Carlo " << count << " of " << repetitions;
    largest_analytic = std::max(largest_analytic, analytic);
    ++checked;
  }
  EXPECT_EQ(checked, 4);
  EXPECT_GT(largest_analytic, 0.05);  // at least one comparison where P is not tiny
}

// Is the binary's "evenly spaced subsets: analytic 0.0403, Monte Carlo 0.0040 +- 0.0464" a
// disagreement? The analytic model says a subset's endpoint lies around the full-data one
// with covariance J Sigma_N J^T (1 - N / N_full). The 18 disjoint evenly spaced subsets of
// the real test at N = 1111 are 18 draws from it: the sum S of their squared Mahalanobis
// distances under that covariance is 18/17 chi^2 with 34 dof (they nearly partition the test,
// so they sum to about zero: 2 x 17 free dimensions). Bounds at the 1e-4 and 1 - 1e-4
// quantiles of chi^2_34 (11.44, 73.48): a false failure in 5000; a spread model wrong by a
// factor of 3 either way fails. The count of wrong decisions among the 18 is then compared
// with the analytic P by an exact binomial test (weak with 18 draws, which is the point).
TEST(MinSamplesOnTheRealTest, EvenlySpacedSubsetsSpreadAsTheAnalyticModelSays) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  CourseModel c;
  ASSERT_TRUE(LoadCourseModel(dir, &c));
  const CalibrationTest& test = c.data.test;
  const int full = test.size();
  const int n = 1111;
  const int subsets = full / n;
  ASSERT_EQ(subsets, 18);
  const Eigen::Matrix4d design = BaselineCovarianceForDesign(DesignAngles("uniform", n), 9.8,
                                                             c.data.conditions.noise_variance_x,
                                                             c.data.conditions.noise_variance_y);
  const Eigen::Matrix2d spread =
      c.trajectory.jacobian * design * c.trajectory.jacobian.transpose() * (1.0 - double(n) / full);
  const Eigen::Matrix2d decision =
      c.trajectory.jacobian * design * c.trajectory.jacobian.transpose() + c.trajectory.noise_part;
  const double analytic = ProbabilityOfWrongLandmark(c.trajectory.endpoint, spread, decision,
                                                     c.data.landmarks, c.truth);
  const Eigen::Matrix2d metric = spread.inverse();
  const double stride = static_cast<double>(full) / n;
  double statistic = 0.0;
  int wrong = 0;
  for (int k = 0; k < subsets; ++k) {
    CalibrationTest subset;
    for (int i = 0; i < n; ++i) {
      const int index = static_cast<int>(k + 0.5 + i * stride);
      ASSERT_LT(index, full);
      subset.theta_rad.push_back(test.theta_rad[index]);
      subset.measured_x.push_back(test.measured_x[index]);
      subset.measured_y.push_back(test.measured_y[index]);
    }
    LinearLsOptions options = LinearLsOptionsFor(c.data.conditions, kCourseGravityMps2);
    BaselineFit fit;
    ASSERT_TRUE(EstimateLinearLs(subset, options, &fit).ok());
    TrajectoryOptions trajectory_options;
    trajectory_options.path_stride = c.data.run.size();
    DeadReckoningResult trajectory;
    ASSERT_TRUE(
        DeadReckon(c.data.run, c.data.conditions, fit, trajectory_options, &trajectory).ok());
    const Eigen::Vector2d d = trajectory.endpoint - c.trajectory.endpoint;
    statistic += d.dot(metric * d);
    wrong +=
        DecideLandmark(trajectory.endpoint, trajectory.covariance, c.data.landmarks, 0.01).best !=
        c.truth;
  }
  const double chi2_34 = statistic * (subsets - 1) / subsets;
  const double p_value = BinomialTwoSidedPValue(wrong, subsets, analytic);
  std::printf(
      "evenly spaced subsets, N = %d: spread statistic %.1f (chi^2_34, expected 34); wrong %d "
      "of %d, analytic P %.4f (binomial p %.2f)\n",
      n, chi2_34, wrong, subsets, analytic, p_value);
  EXPECT_GT(chi2_34, 11.44);
  EXPECT_LT(chi2_34, 73.48);
  EXPECT_GT(analytic, 0.02);
  EXPECT_GE(p_value, 1e-4);
}

}  // namespace
}  // namespace accelcal

namespace accelcal {
namespace {

// The explanation quotes the N of a design that ran and names it: with --design=two alone it
// once quoted the optimal design's search default (N = 100) as if it were a result.
TEST(MinSamplesBinary, TheExplanationQuotesTheNOfADesignThatRan) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  const testing::CommandResult result =
      testing::RunBinary("min_samples", "--data_dir='" + dir + "' --design=two --repetitions=0");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const size_t at = result.stdout_text.find("design two       N_min = ");
  ASSERT_NE(at, std::string::npos) << result.stdout_text;
  const int n_min = std::atoi(result.stdout_text.c_str() + at + 25);
  EXPECT_NE(result.stdout_text.find("N = " + std::to_string(n_min) +
                                    " samples (design two) keep P(wrong) <= 0.01"),
            std::string::npos)
      << result.stdout_text;
}

}  // namespace
}  // namespace accelcal
