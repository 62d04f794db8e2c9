// The library built with one effect of a research project's own (scale_cubic.h, one
// registration line in registered_effects.h): the effect reaches the catalogue, the
// simulator, both residuals, dead reckoning and discovery without any other change, and
// discovery names it when it is hidden in simulated data and finds nothing when nothing is.

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>

#include "estimation/tilt_table/discovery.h"
#include "estimation/tilt_table/joint_estimator.h"
#include "estimation/tilt_table/trajectory.h"
#include "io/scenario_json.h"
#include "models/sensor_model.h"
#include "residuals/compressed_calibration_residual.h"
#include "scale_cubic.h"
#include "simulation/scenario.h"

namespace accelcal {
namespace {

constexpr Parameter kCubicX = ParameterOf<ScaleCubic>(SensingAxis::kX);
constexpr Parameter kCubicY = ParameterOf<ScaleCubic>(SensingAxis::kY);

TEST(ExtendedCatalogue, AppendsTheNewEffectAfterTheBuiltInOnes) {
  ASSERT_EQ(kParameterCount, 16);
  EXPECT_STREQ(Info(Parameter::kNoiseVarianceY).name, "noise_variance_y");  // unchanged
  EXPECT_EQ(Parameter::kNoiseVarianceY.index(), 13);
  EXPECT_EQ(kCubicX.index(), 14);
  EXPECT_STREQ(Info(kCubicX).name, "scale_cubic_x");
  EXPECT_STREQ(Info(kCubicY).unit, "1/(m/s^2)^2");
  EXPECT_STREQ(Info(kCubicY).meaning, "third-order scale term of the y axis (IEEE 1293 K3)");
  ASSERT_NE(FindParameter("scale_cubic_y"), nullptr);
  EXPECT_EQ(FindParameter("scale_cubic_y")->parameter, kCubicY);
  std::vector<Parameter> effects;
  ASSERT_TRUE(ParseEffects("scale_cubic_x,angle_offset", &effects).ok());
  EXPECT_EQ(effects, (std::vector<Parameter>{kCubicX, Parameter::kAngleOffset}));
}

TEST(ExtendedCatalogue, TheNewEffectIsABlockOfEachResidualItActsIn) {
  const auto test_x = CalibrationParameters(SensingAxis::kX);
  const auto test_y = CalibrationParameters(SensingAxis::kY);
  const auto run = RunParameters();
  EXPECT_EQ(test_x.size(), 7u);
  EXPECT_NE(std::find(test_x.begin(), test_x.end(), kCubicX), test_x.end());
  EXPECT_EQ(std::find(test_x.begin(), test_x.end(), kCubicY), test_x.end());
  EXPECT_NE(std::find(test_y.begin(), test_y.end(), kCubicY), test_y.end());
  EXPECT_EQ(run.size(), 11u);
  EXPECT_NE(std::find(run.begin(), run.end(), kCubicX), run.end());
  EXPECT_NE(std::find(run.begin(), run.end(), kCubicY), run.end());
}

// A scenario key like any other; with no noise the simulated test is the baseline's
// prediction plus k3 f^3 exactly.
TEST(ScaleCubic, TheSimulatorAddsItsTerm) {
  Scenario scenario;
  ASSERT_TRUE(LoadDefaultScenario(&scenario).ok());
  ASSERT_TRUE(ApplyScenarioOverrides("scale_cubic_y=0.001,tilt_samples=101,noise_variance_x=1e-30,"
                                     "noise_variance_y=1e-30",
                                     &scenario)
                  .ok());
  const SimulatedData data = SimulateScenario(scenario, 1);
  ModelParameters<double> without = scenario.truth.parameters;
  without[kCubicY] = 0.0;
  for (int i = 0; i < data.test.size(); i += 10) {
    const double theta = data.test.theta_rad[i];
    const double u = DriftCoordinate(i, data.test.size());
    const double force_y = -9.8 * std::cos(theta);
    EXPECT_NEAR(
        data.test.measured_y[i] - PredictCalibrationOutput(theta, u, SensingAxis::kY, 9.8, without),
        0.001 * force_y * force_y * force_y, 1e-12);
    EXPECT_NEAR(data.test.measured_x[i],
                PredictCalibrationOutput(theta, u, SensingAxis::kX, 9.8, without), 1e-12);
  }
}

// The run's inverse is no longer closed-form: Newton steps after the quadratic root. They
// invert the forward model, and their derivative with respect to k3 is the implicit one,
// d f / d k3 = -f^3 / (dm/df), even at k3 = 0 (where the steps change no value).
TEST(ScaleCubic, TheRunsInverseAndItsDerivativeAreExact) {
  using Jet = ceres::Jet<double, 1>;
  for (const double k3 : {0.0, 2e-4, -1e-3}) {
    ModelParameters<Jet> p;
    p[Parameter::kBiasY] = Jet(0.05);
    p[Parameter::kScaleY] = Jet(-0.02);
    p[Parameter::kScaleNonlinearityY] = Jet(0.001);
    p[kCubicY] = Jet(k3, 0);
    const RunCorrection<Jet> correct(p);
    for (const double force : {-9.0, -2.0, 0.5, 6.0}) {
      const Jet measured = AxisOutput(Jet(force), p, SensingAxis::kY, 0.0, Phase::kVehicleRun);
      const Jet recovered = correct.AlongAxis(Jet(measured.a), SensingAxis::kY);
      EXPECT_NEAR(recovered.a, force, 1e-12) << k3;
      const double slope = 0.98 + 2 * 0.001 * force + 3 * k3 * force * force;
      EXPECT_NEAR(recovered.v[0], -force * force * force / slope, 1e-9) << k3;
    }
  }
}

// sin^3 is not in the compressed tilt residual's basis: it says so, and the joint solve,
// asked for the compressed residuals, uses the per-sample ones instead: one residual block
// per sample and axis, the per-sample solve's estimates exactly, and the hidden k3 recovered.
TEST(ScaleCubic, TheCompressedResidualDeclinesAndTheSolveFallsBack) {
  Scenario scenario;
  ASSERT_TRUE(LoadDefaultScenario(&scenario).ok());
  ASSERT_TRUE(ApplyScenarioOverrides("scale_cubic_y=2e-4", &scenario).ok());
  const SimulatedData data = SimulateScenario(scenario, 2);
  const AxisNoise noise[2] = {{0.25}, {0.64}};
  std::unique_ptr<CompressedCalibrationResidual> residuals[2];
  const Status status = CompressedCalibrationResidual::Make(data.test, 9.8, noise,
                                                            ModelParameters<double>(), residuals);
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find("not a combination of the compressed basis"), std::string::npos);

  JointOptions options;
  options.noise_variance_x = 0.25;
  options.noise_variance_y = 0.64;
  ASSERT_TRUE(ParseEffects("scale_cubic_y", &options.effects).ok());
  options.compress_calibration = true;
  JointResult asked_compressed;
  const Status solved =
      SolveJoint(data.test, data.run, data.conditions, data.landmarks, options, &asked_compressed);
  ASSERT_TRUE(solved.ok()) << solved.message();
  EXPECT_EQ(asked_compressed.solver.residual_blocks, 2 * data.test.size());
  options.compress_calibration = false;
  JointResult per_sample;
  ASSERT_TRUE(
      SolveJoint(data.test, data.run, data.conditions, data.landmarks, options, &per_sample).ok());
  ASSERT_EQ(asked_compressed.estimate.free, per_sample.estimate.free);
  for (const Parameter parameter : per_sample.estimate.free) {
    EXPECT_EQ(asked_compressed.estimate.Value(parameter), per_sample.estimate.Value(parameter))
        << Info(parameter).name;
  }
  // The truth within 3 sigma (a false failure once in 370 seeds; seed 2 is fixed).
  const double z = (asked_compressed.estimate.Value(kCubicY) - 2e-4) /
                   asked_compressed.estimate.StandardDeviation(kCubicY);
  EXPECT_LT(std::abs(z), 3.0);
}

DiscoveryResult DiscoverIn(const std::string& assignments, uint64_t seed) {
  Scenario scenario;
  EXPECT_TRUE(LoadDefaultScenario(&scenario).ok());
  EXPECT_TRUE(ApplyScenarioOverrides(assignments, &scenario).ok());
  const SimulatedData data = SimulateScenario(scenario, seed);
  DiscoveryOptions options;
  DiscoveryResult result;
  const Status status =
      Discover(data.test, data.run, data.conditions, data.landmarks, options, &result);
  EXPECT_TRUE(status.ok()) << status.message();
  return result;
}

// Hidden at its example size (about 7 sigma) in the course-sized experiment: discovery
// names scale_cubic_y and nothing else, and its estimate is within 3 sigma of the truth.
TEST(ScaleCubic, DiscoveryNamesItWhenHiddenAndEstimatesItWithinThreeSigma) {
  for (const uint64_t seed : {11u, 12u}) {
    const DiscoveryResult result = DiscoverIn("scale_cubic_y=2e-4", seed);
    ASSERT_EQ(result.effects.size(), 1u) << seed;
    EXPECT_EQ(result.effects[0].effect, kCubicY);
    const double z = (result.effects[0].estimate - 2e-4) / result.effects[0].stddev;
    EXPECT_LT(std::abs(z), 3.0) << seed << ": estimate " << result.effects[0].estimate << " +- "
                                << result.effects[0].stddev;
    EXPECT_LT(result.cross_validation.extended, result.cross_validation.baseline);
  }
}

// With nothing hidden, the extended catalogue's candidates (the new effect among them)
// name nothing.
TEST(ScaleCubic, DiscoveryFindsNothingWhenNothingIsHidden) {
  for (const uint64_t seed : {21u, 22u}) {
    const DiscoveryResult result = DiscoverIn("", seed);
    EXPECT_TRUE(result.effects.empty()) << seed << ": " << Info(result.effects[0].effect).name;
    bool scored = false;
    for (const CandidateScore& candidate : result.candidates) scored |= candidate.effect == kCubicY;
    EXPECT_TRUE(scored) << "scale_cubic_y was not a candidate";
  }
}

}  // namespace
}  // namespace accelcal
