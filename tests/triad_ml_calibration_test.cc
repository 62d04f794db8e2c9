// The maximum-likelihood triad calibration (estimation/triad/triad_ml_calibration.h) on simulated
// static poses (simulation/triad_simulator.h) whose truth and noise are known: the truth
// within 3 sigma, the reported sigma against a Monte Carlo spread, and the refusals of pose
// sets that cannot determine the triad.

#include "estimation/triad/triad_ml_calibration.h"

#include <ceres/gradient_checker.h>
#include <ceres/sphere_manifold.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "estimation/triad/triad_initial_guess.h"
#include "models/triad.h"
#include "residuals/triad_pose_residual.h"
#include "simulation/triad_simulator.h"
#include "studies/triad_monte_carlo.h"
#include "triad_test_session.h"

namespace accelcal {
namespace {

constexpr double kGravity = testing::kTriadTestGravity;

// A triad close to the Xsens unit of imu_tk's example (the study's default truth).
TriadParameters Truth() { return XsensLikeTriad(); }

using testing::TriadTestMlOptions;
using testing::TriadTestSimulationOptions;

TEST(TriadPoseResidual, IsZeroAtTheTruth) {
  const TriadParameters truth = Truth();
  const double direction[3] = {0.6, -0.48, 0.64};
  const double force[3] = {kGravity * direction[0], kGravity * direction[1],
                           kGravity * direction[2]};
  std::array<double, 3> raw;
  TriadRawOutput(truth.data(), force, raw.data());
  const TriadPoseResidual residual(raw, {0.3, 0.3, 0.3}, kGravity);
  double r[3];
  ASSERT_TRUE(residual(truth.data(), direction, r));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r[k], 0.0, 1e-9);
  // And with second-order scale terms, through the effects' block: TriadPredictOutput is
  // TriadRawOutput's expression.
  const TriadScaleNonlinearity k2 = {2e-4, -1e-4, 3e-4};
  TriadRawOutput(truth.data(), k2.data(), force, raw.data());
  TriadEffectCoefficients effects{};
  const int first_k2 = TriadEffectCoefficientIndex("scale_nonlinearity_x");
  for (int k = 0; k < 3; ++k) effects[first_k2 + k] = k2[k];
  const TriadPoseResidual quadratic(raw, {0.3, 0.3, 0.3}, kGravity);
  ASSERT_TRUE(quadratic(truth.data(), effects.data(), direction, r));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(r[k], 0.0, 1e-9);
}

TEST(TriadMlCalibration, RecoversASimulatedTriadWithin3Sigma) {
  RandomSource random(20, 1);
  const std::vector<TriadPoseMean> poses =
      SimulateTriadPoses(TriadTestSimulationOptions(), RandomPoseDirections(30, &random), &random);
  TriadMlResult result;
  const Status status = CalibrateTriadMl(poses, TriadTestMlOptions(), &result);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(result.degrees_of_freedom, 21);
  const TriadParameters truth = Truth();
  for (int p = 0; p < kTriadParameterCount; ++p) {
    EXPECT_GT(result.stddev[p], 0.0);
    EXPECT_LT(std::abs(result.parameters[p] - truth[p]), 3.0 * result.stddev[p])
        << TriadParameterInfos()[p].name << " " << result.parameters[p] << " +- "
        << result.stddev[p];
  }
  // The pooled noise is the simulated one, and the white noise model explains the residuals.
  EXPECT_NEAR(std::sqrt(result.noise_variance[0]), 3.0, 0.15);
  EXPECT_GT(result.p_value, 0.001);
}

// Over kTrials independent sessions of 30 random poses: the standard deviation of each
// estimate against the mean reported sigma. With 1000 trials the spread is known to about
// 2.2% (1/sqrt(2 n)), so the issue's [0.9, 1.1] is a 4.5-sigma band.
TEST(TriadMlCalibration, ReportedSigmaMatchesTheMonteCarloSpread) {
  constexpr int kTrials = 1000;
  const TriadParameters truth = Truth();
  std::array<double, kTriadParameterCount> sum{}, sum_squares{}, sum_sigma{};
  std::array<int, kTriadParameterCount> within_3_sigma{};
  for (int trial = 0; trial < kTrials; ++trial) {
    RandomSource random(2020, trial);
    // The same pose set in every trial: the covariance is conditional on the poses.
    RandomSource pose_random(7, 0);
    const std::vector<TriadPoseMean> poses = SimulateTriadPoses(
        TriadTestSimulationOptions(), RandomPoseDirections(30, &pose_random), &random);
    TriadMlResult result;
    const Status status = CalibrateTriadMl(poses, TriadTestMlOptions(), &result);
    ASSERT_TRUE(status.ok()) << "trial " << trial << ": " << status.message();
    for (int p = 0; p < kTriadParameterCount; ++p) {
      const double error = result.parameters[p] - truth[p];
      sum[p] += error;
      sum_squares[p] += error * error;
      sum_sigma[p] += result.stddev[p];
      if (std::abs(error) < 3.0 * result.stddev[p]) ++within_3_sigma[p];
    }
  }
  for (int p = 0; p < kTriadParameterCount; ++p) {
    const double mean = sum[p] / kTrials;
    const double spread = std::sqrt((sum_squares[p] - kTrials * mean * mean) / (kTrials - 1));
    const double ratio = (sum_sigma[p] / kTrials) / spread;
    const char* name = TriadParameterInfos()[p].name;
    RecordProperty(std::string("sigma_ratio_") + name, std::to_string(ratio));
    std::printf("  %-16s reported sigma / Monte Carlo spread = %.3f, within 3 sigma %d/%d\n", name,
                ratio, within_3_sigma[p], kTrials);
    EXPECT_GT(ratio, 0.9) << name;
    EXPECT_LT(ratio, 1.1) << name;
    EXPECT_GE(within_3_sigma[p], 0.99 * kTrials) << name;
  }
}

// Every pose a rotation about the sensor's x axis: gravity never has an x component, so the
// x output is (yz v_y - zy v_z) / gain_x + b_x, and to first order each pose's out-of-plane
// tilt absorbs its x residual: gain_x, offset_x (and the angles with them) are not determined.
TEST(TriadMlCalibration, RefusesPosesInAPlaneNamingTheUnidentifiableParameters) {
  RandomSource random(5, 0);
  std::vector<std::array<double, 3>> directions;
  for (int i = 0; i < 20; ++i) {
    const double angle = 2.0 * M_PI * i / 20.0;
    directions.push_back({0.0, std::cos(angle), std::sin(angle)});
  }
  const std::vector<TriadPoseMean> poses =
      SimulateTriadPoses(TriadTestSimulationOptions(), directions, &random);
  TriadMlResult result;
  const Status status = CalibrateTriadMl(poses, TriadTestMlOptions(), &result);
  ASSERT_FALSE(status.ok());
  const std::string& message = status.message();
  std::printf("  refusal: %s\n", message.c_str());
  EXPECT_NE(message.find("not identifiable"), std::string::npos) << message;
  EXPECT_NE(message.find("gain_x"), std::string::npos) << message;
  EXPECT_NE(message.find("offset_x"), std::string::npos) << message;
  EXPECT_NE(message.find("lie within a few degrees of a plane"), std::string::npos) << message;
}

// Poses bunched within 3 degrees of one direction, started as calibrate_imu starts (from the
// poses themselves): refused as too weakly determined, with the pose means' spans and the poses
// to hold, never with advice to iterate longer (the refusal once said "raise
// --max_iterations", a flag calibrate_imu does not have).
TEST(TriadMlCalibration, RefusesPosesBunchedAroundOneDirection) {
  for (const double tilt : {0.05, 0.087, 0.1}) {  // rad, the cone's half-angle
    RandomSource random(6, 0);
    std::vector<std::array<double, 3>> directions;
    for (int i = 0; i < 20; ++i) {
      const double angle = 2.0 * M_PI * i / 20.0;
      directions.push_back(
          {tilt * std::cos(angle), tilt * std::sin(angle), std::sqrt(1.0 - tilt * tilt)});
    }
    const std::vector<TriadPoseMean> poses =
        SimulateTriadPoses(TriadTestSimulationOptions(), directions, &random);
    TriadMlOptions options = TriadTestMlOptions();
    options.initial = TriadStartFromPoses(poses, kGravity);
    TriadMlResult result;
    const Status status = CalibrateTriadMl(poses, options, &result);
    ASSERT_FALSE(status.ok()) << tilt;
    const std::string& message = status.message();
    std::printf("  %g rad: %s\n", tilt, message.c_str());
    EXPECT_EQ(message.find("max_iterations"), std::string::npos) << message;
    EXPECT_TRUE(message.find("too weakly") != std::string::npos ||
                message.find("not identifiable") != std::string::npos)
        << message;
    EXPECT_NE(message.find(" up"), std::string::npos) << message;
  }
}

TEST(TriadMlCalibration, RefusesFewerThanTenPoses) {
  for (const int count : {6, 9}) {
    RandomSource random(11, count);
    const std::vector<TriadPoseMean> poses = SimulateTriadPoses(
        TriadTestSimulationOptions(), RandomPoseDirections(count, &random), &random);
    TriadMlResult result;
    const Status status = CalibrateTriadMl(poses, TriadTestMlOptions(), &result);
    ASSERT_FALSE(status.ok()) << count << " poses";
    std::printf("  refusal: %s\n", status.message().c_str());
    if (count < 9) {
      EXPECT_NE(status.message().find("not identifiable"), std::string::npos) << status.message();
    } else {
      EXPECT_NE(status.message().find("0 degrees of freedom"), std::string::npos)
          << status.message();
    }
  }
}

// The second-order scale terms used below (1/(m/s^2)): 8 to 23 counts at 1 g along an axis.
const TriadScaleNonlinearity kScaleNonlinearity = ExampleScaleNonlinearity();
const int kFirstK2 = TriadEffectCoefficientIndex("scale_nonlinearity_x");

// kScaleNonlinearity in the effects' block.
TriadEffectCoefficients ScaleNonlinearityEffects() {
  TriadEffectCoefficients effects{};
  for (int k = 0; k < 3; ++k) effects[kFirstK2 + k] = kScaleNonlinearity[k];
  return effects;
}

TEST(TriadMlModel, ScaleNonlinearityRoundTripsAndMatchesTheTiltTableSign) {
  const TriadParameters truth = Truth();
  const double force[3] = {-4.1, 7.3, 5.2};  // m/s^2
  double raw[3], linear_raw[3], back[3];
  TriadRawOutput(truth.data(), kScaleNonlinearity.data(), force, raw);
  TriadRawOutput(truth.data(), force, linear_raw);
  ASSERT_TRUE(TriadSpecificForce(truth.data(), kScaleNonlinearity.data(), raw, back));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], force[k], 1e-12) << k;
  // Positive k2 makes the axis read more, as m_k += k2_k f_k^2 does on the tilt table: on z,
  // (w_z = f_z) the output rises by k2_z f_z^2 / gain_z counts.
  EXPECT_NEAR(raw[2] - linear_raw[2],
              kScaleNonlinearity[2] * force[2] * force[2] / truth[kTriadGainZ], 1e-9);
  // k2 = 0 is the 9-parameter model to the last bit.
  const TriadScaleNonlinearity zero{};
  double zero_raw[3];
  TriadRawOutput(truth.data(), zero.data(), force, zero_raw);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(zero_raw[k], linear_raw[k]);
}

// The Jacobian autodiff gives the solver and ceres::Covariance against central differences,
// in the direction's tangent space, at a point where the residual is not zero.
TEST(TriadResidual, GradientCheckerAgreesWithAutodiff) {
  const TriadParameters parameters = Truth();
  std::array<double, 3> direction = {0.48, -0.6, 0.64};
  const std::array<double, 3> mean = {33200.0, 30800.0, 35100.0};
  const std::array<double, 3> mean_stddev = {0.3, 0.25, 0.35};
  ceres::SphereManifold<3> sphere;
  // The checker differentiates by Ridders' method, whose first step (a relative 1e-2, and at
  // least that absolutely) would move a gain of 0.0024 (m/s^2)/count by four times itself.
  ceres::NumericDiffOptions numeric;
  numeric.ridders_relative_initial_step_size = 1e-6;
  {
    const std::unique_ptr<ceres::CostFunction> cost(
        TriadPoseResidual::Create(mean, mean_stddev, kGravity));
    const std::vector<const ceres::Manifold*> manifolds = {nullptr, &sphere};
    ceres::GradientChecker checker(cost.get(), &manifolds, numeric);
    const std::vector<const double*> blocks = {parameters.data(), direction.data()};
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(blocks.data(), 1e-7, &results)) << results.error_log;
  }
  {
    // Every effect at a small non-zero value, 20 s after the time origin (so that the drift's
    // column is not zero).
    TriadPoseContext context;
    context.time_s = 20.0;
    TriadEffectCoefficients effects = ScaleNonlinearityEffects();
    for (int c = 0; c < kTriadEffectCoefficientCount; ++c)
      if (effects[c] == 0.0) effects[c] = 1e-3;
    const std::unique_ptr<ceres::CostFunction> cost(
        TriadPoseResidual::CreateWithEffects(mean, mean_stddev, kGravity, context));
    const std::vector<const ceres::Manifold*> manifolds = {nullptr, nullptr, &sphere};
    ceres::GradientChecker checker(cost.get(), &manifolds, numeric);
    const std::vector<const double*> blocks = {parameters.data(), effects.data(), direction.data()};
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(blocks.data(), 1e-7, &results)) << results.error_log;
    // The k2 columns are there: d r_k / d k2_k = -w_k^2 / (gain_k sigma_k) is far from zero.
    for (int k = 0; k < 3; ++k)
      EXPECT_GT(std::abs(results.jacobians[1](k, kFirstK2 + k)), 100.0) << k;
  }
}

TriadMlOptions TwelveParameterOptions() {
  TriadMlOptions options = TriadTestMlOptions();
  options.scale_nonlinearity = true;
  return options;
}

TEST(TriadMlCalibration, RecoversTheScaleNonlinearityWithin3Sigma) {
  TriadSimulationOptions simulation = TriadTestSimulationOptions();
  simulation.effects = ScaleNonlinearityEffects();
  RandomSource random(20, 2);
  const std::vector<TriadPoseMean> poses =
      SimulateTriadPoses(simulation, RandomPoseDirections(30, &random), &random);
  TriadMlResult result;
  const Status status = CalibrateTriadMl(poses, TwelveParameterOptions(), &result);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(result.degrees_of_freedom, 18);
  const TriadParameters truth = Truth();
  for (int p = 0; p < kTriadParameterCount; ++p) {
    EXPECT_LT(std::abs(result.parameters[p] - truth[p]), 3.0 * result.stddev[p])
        << TriadParameterInfos()[p].name;
  }
  for (int k = 0; k < kTriadScaleNonlinearityCount; ++k) {
    const double error = result.effects[kFirstK2 + k] - kScaleNonlinearity[k];
    EXPECT_LT(std::abs(error), 3.0 * result.effects_stddev[kFirstK2 + k])
        << TriadScaleNonlinearityInfos()[k].name;
    // Determined well enough to tell from zero (sigma ~1e-5 1/(m/s^2) with 30 poses).
    EXPECT_LT(result.effects_stddev[kFirstK2 + k], 0.2 * std::abs(kScaleNonlinearity[k]));
  }
  EXPECT_GT(result.p_value, 0.001);
  // The 9-parameter fit of the same poses does not explain them: k2 is in the data.
  TriadMlResult nine;
  ASSERT_TRUE(CalibrateTriadMl(poses, TriadTestMlOptions(), &nine).ok());
  EXPECT_LT(nine.p_value, 1e-6) << nine.chi2_per_dof;
}

// Without the option nothing changes: the 9-parameter fit reports no k2, and the
// 12-parameter fit of data without k2 finds k2 at zero within 3 sigma.
TEST(TriadMlCalibration, ScaleNonlinearityOptionOffLeavesTheNineParameterFit) {
  RandomSource random(20, 1);
  const std::vector<TriadPoseMean> poses =
      SimulateTriadPoses(TriadTestSimulationOptions(), RandomPoseDirections(30, &random), &random);
  TriadMlResult nine, twelve;
  ASSERT_TRUE(CalibrateTriadMl(poses, TriadTestMlOptions(), &nine).ok());
  EXPECT_TRUE(nine.effects_estimated.empty());
  for (double value : nine.effects) EXPECT_EQ(value, 0.0);
  ASSERT_TRUE(CalibrateTriadMl(poses, TwelveParameterOptions(), &twelve).ok());
  EXPECT_EQ(twelve.effects_estimated.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(std::abs(twelve.effects[kFirstK2 + k]), 3.0 * twelve.effects_stddev[kFirstK2 + k]);
  }
  // Estimating three more parameters costs precision, never gains it.
  for (int p = 0; p < kTriadParameterCount; ++p) EXPECT_GE(twelve.stddev[p], nine.stddev[p]);
}

// A degenerate pose set is refused with the poses to add; holding those as well makes the
// triad identifiable, so the advice is right, not only printed.
void ExpectSuggestedPosesMakeItIdentifiable(const std::vector<std::array<double, 3>>& directions,
                                            const TriadMlOptions& options, const char* label) {
  TriadSimulationOptions simulation = TriadTestSimulationOptions();
  if (options.scale_nonlinearity) simulation.effects = ScaleNonlinearityEffects();
  RandomSource random(31, 0);
  TriadMlResult refused;
  const Status status =
      CalibrateTriadMl(SimulateTriadPoses(simulation, directions, &random), options, &refused);
  ASSERT_FALSE(status.ok()) << label;
  std::printf("  %s: %s\n", label, status.message().c_str());
  ASSERT_FALSE(refused.suggested_directions.empty()) << label;
  EXPECT_NE(status.message().find(" held with "), std::string::npos) << status.message();
  std::vector<std::array<double, 3>> more = directions;
  more.insert(more.end(), refused.suggested_directions.begin(), refused.suggested_directions.end());
  TriadMlResult fitted;
  const Status fixed =
      CalibrateTriadMl(SimulateTriadPoses(simulation, more, &random), options, &fitted);
  EXPECT_TRUE(fixed.ok()) << label << ": " << fixed.message();
}

std::vector<std::array<double, 3>> AboutX(int count) {
  std::vector<std::array<double, 3>> directions;
  for (int i = 0; i < count; ++i) {
    const double angle = 2.0 * M_PI * i / count;
    directions.push_back({0.0, std::cos(angle), std::sin(angle)});
  }
  return directions;
}

TEST(TriadMlCalibration, RefusalOfPlanarPosesSaysToHoldTheMissingAxisUpAndDown) {
  for (const TriadMlOptions& options : {TriadTestMlOptions(), TwelveParameterOptions()}) {
    RandomSource random(5, 0);
    TriadMlResult result;
    ASSERT_FALSE(
        CalibrateTriadMl(SimulateTriadPoses(TriadTestSimulationOptions(), AboutX(20), &random),
                         options, &result)
            .ok());
    // The first two poses to add: x up and x down, the axis the turns about x never showed.
    ASSERT_GE(result.suggested_directions.size(), 2u);
    EXPECT_GT(std::abs(result.suggested_directions[0][0]), 0.99);
    EXPECT_GT(std::abs(result.suggested_directions[1][0]), 0.99);
    EXPECT_LT(result.suggested_directions[0][0] * result.suggested_directions[1][0], 0.0);
    ExpectSuggestedPosesMakeItIdentifiable(AboutX(20), options,
                                           options.scale_nonlinearity ? "planar, 12" : "planar, 9");
  }
}

TEST(TriadMlCalibration, RefusalOfSixAndOfFewPosesNamesPosesThatFixIt) {
  const std::vector<std::array<double, 3>> six = SixPoseDirections();
  ExpectSuggestedPosesMakeItIdentifiable(six, TriadTestMlOptions(), "six, 9");
  ExpectSuggestedPosesMakeItIdentifiable(six, TwelveParameterOptions(), "six, 12");
  RandomSource random(11, 8);
  ExpectSuggestedPosesMakeItIdentifiable(RandomPoseDirections(8, &random), TriadTestMlOptions(),
                                         "8, 9");
  ExpectSuggestedPosesMakeItIdentifiable(RandomPoseDirections(11, &random),
                                         TwelveParameterOptions(), "11, 12");
  ExpectSuggestedPosesMakeItIdentifiable(RandomPoseDirections(9, &random), TriadTestMlOptions(),
                                         "9 (no dof), 9");
}

}  // namespace
}  // namespace accelcal
