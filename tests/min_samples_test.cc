// How many samples: the wrong-landmark probability against brute-force sampling, the
// design covariance against the estimator's own, N_min monotone in the criterion, and
// the analytic curve against a full-simulation Monte Carlo.

#include "studies/min_samples.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <nlohmann/json.hpp>

#include "estimation/landmark_decision.h"
#include "estimation/linear_ls.h"
#include "estimation/trajectory.h"
#include "io/scenario_json.h"
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
  monte_carlo.progress = false;
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

TEST(MinSamplesBinary, AnswersTheReportsQuestionOnTheCourseData) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  testing::ScratchDir out;
  const testing::CommandResult result = testing::RunBinary(
      "min_samples", "--data_dir='" + dir + "' --design=all --repetitions=200 --json='" +
                         out.File("m.json") + "'");
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  // The report's own per-axis gaps, found from the landmarks.
  EXPECT_NE(result.stdout_text.find("d_min,x = 1.62 m\n  (C-D) and d_min,y = 13.26 m (C-A)"),
            std::string::npos)
      << result.stdout_text;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out.File("m.json")));
  EXPECT_EQ(json["truth"], "C");
  ASSERT_EQ(json["designs"].size(), 4u);
  for (const auto& design : json["designs"]) {
    // Every balanced design needs about the same N: the bias dominates the parameter
    // part, and no design estimates a bias better than sigma^2 / N.
    EXPECT_NEAR(design["n_min"].get<int>(), 4447, 5) << design["name"];
    EXPECT_NEAR(design["n_min_3sigma"].get<int>(), 752, 5) << design["name"];
    // 4 binomial sd, plus 2/200 for the cells where p is near 0 and the sd vanishes (the
    // tight comparison is AnalyticCurveAgreesWithFullSimulation above).
    for (const auto& check : design["monte_carlo"]) {
      EXPECT_NEAR(check["monte_carlo"].get<double>(), check["analytic"].get<double>(),
                  4 * check["monte_carlo_sd"].get<double>() + 0.01)
          << design["name"] << " " << check["kind"] << " N = " << check["n"];
    }
  }
  testing::ExpectBadInputContract(testing::RunBinary("min_samples", "--design=six"), "min_samples",
                                  "--design must be uniform, four, two, optimal or all");
}

}  // namespace
}  // namespace accelcal
