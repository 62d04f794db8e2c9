// The joint problem's supporting modules: the data prepared once
// (estimation/tilt_table/joint_data.h), the identifiability check
// (estimation/solver/identifiability.h), discovery's score test
// (estimation/tilt_table/score_test.h), effects by name (models/effect_names.h) and the robust
// loss's names (estimation/tilt_table/joint_estimator.h).

#include "estimation/tilt_table/joint_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "estimation/solver/identifiability.h"
#include "estimation/tilt_table/joint_estimator.h"
#include "estimation/tilt_table/linear_ls.h"
#include "estimation/tilt_table/score_test.h"
#include "io/scenario_json.h"
#include "models/effect_names.h"
#include "models/tilt_table.h"
#include "simulation/scenario.h"

namespace accelcal {
namespace {

JointOptions StatedNoise(const RunConditions& conditions) {
  JointOptions options = JointOptionsFor(conditions, kCourseGravityMps2);
  return options;
}

SimulatedData Simulate(const std::string& overrides, uint64_t seed) {
  Scenario scenario;
  EXPECT_TRUE(LoadDefaultScenario(&scenario).ok());
  if (!overrides.empty()) EXPECT_TRUE(ApplyScenarioOverrides(overrides, &scenario).ok());
  return SimulateScenario(scenario, seed);
}

TEST(JointData, TheBaselineIsTheLinearFitComputedOncePerNoiseModel) {
  const SimulatedData data = Simulate("", 3);
  const JointData prepared(data.test, data.run, data.conditions, data.landmarks);
  const JointOptions options = StatedNoise(data.conditions);
  const BaselineFit* fit = nullptr;
  ASSERT_TRUE(prepared.Baseline(options, &fit).ok());
  LinearLsOptions linear = LinearLsOptionsFor(data.conditions, kCourseGravityMps2);
  BaselineFit expected;
  ASSERT_TRUE(EstimateLinearLs(data.test, linear, &expected).ok());
  EXPECT_EQ(fit->parameters, expected.parameters);
  EXPECT_EQ(fit->covariance, expected.covariance);

  // The same noise model, asked again (with other effects and another landmark mode): the
  // same fit, not a new one.
  JointOptions other_model = options;
  other_model.effects = {Parameter::kAngleOffset};
  other_model.landmark_mode = JointOptions::Landmark::kAuto;
  const BaselineFit* again = nullptr;
  ASSERT_TRUE(prepared.Baseline(other_model, &again).ok());
  EXPECT_EQ(again, fit);

  // Another noise model is another fit: four times the variance, four times the covariance.
  JointOptions noisier = options;
  noisier.noise_variance_x *= 4.0;
  noisier.noise_variance_y *= 4.0;
  const BaselineFit* scaled = nullptr;
  ASSERT_TRUE(prepared.Baseline(noisier, &scaled).ok());
  ASSERT_NE(scaled, fit);
  EXPECT_NEAR(scaled->covariance(0, 0) / fit->covariance(0, 0), 4.0, 1e-9);
  // The outliers and the correlation belong to the noise model too.
  JointOptions correlated = options;
  correlated.noise_correlation = {0.3, 0.0};
  const DeadReckoningResult* white_run = nullptr;
  const DeadReckoningResult* correlated_run = nullptr;
  ASSERT_TRUE(prepared.BaselineTrajectory(options, &white_run).ok());
  ASSERT_TRUE(prepared.BaselineTrajectory(correlated, &correlated_run).ok());
  EXPECT_NE(white_run, correlated_run);
  // AR(1) noise with rho = 0.3 integrates to a larger endpoint noise than white noise.
  EXPECT_GT(correlated_run->noise_part(0, 0), 1.2 * white_run->noise_part(0, 0));
}

TEST(JointData, SolvesThroughItEqualOneOffSolvesBitForBit) {
  const SimulatedData data =
      Simulate("angle_offset=0.004,nonorthogonality=0.002,run_bias_shift_x=0.02", 5);
  const JointData prepared(data.test, data.run, data.conditions, data.landmarks);
  JointOptions options = StatedNoise(data.conditions);
  options.landmark_mode = JointOptions::Landmark::kAuto;
  for (const char* effects : {"none", "angle_offset", "angle_offset,run_bias_shift_x", "all"}) {
    ASSERT_TRUE(ParseEffects(effects, &options.effects).ok());
    JointResult one_off;
    ASSERT_TRUE(
        SolveJoint(data.test, data.run, data.conditions, data.landmarks, options, &one_off).ok())
        << effects;
    // Twice through the same JointData: the second solve reuses what the first prepared.
    for (int repeat = 0; repeat < 2; ++repeat) {
      JointResult shared;
      ASSERT_TRUE(SolveJoint(prepared, options, &shared).ok()) << effects;
      EXPECT_EQ(shared.landmark, one_off.landmark) << effects;
      EXPECT_EQ(shared.estimate.free, one_off.estimate.free) << effects;
      EXPECT_EQ(shared.estimate.covariance, one_off.estimate.covariance) << effects;
      for (const Parameter parameter : one_off.estimate.free) {
        EXPECT_EQ(shared.estimate.Value(parameter), one_off.estimate.Value(parameter))
            << effects << " " << Info(parameter).name;
      }
      EXPECT_EQ(shared.chi2_x + shared.chi2_y + shared.chi2_endpoint,
                one_off.chi2_x + one_off.chi2_y + one_off.chi2_endpoint)
          << effects;
    }
  }
}

// For an effect linear in its parameter (the bias drift adds d_k u_i to axis k), the score
// statistic is exactly the chi-square that adding the effect and solving again removes;
// for a nonlinear one (the angle offset) it is the first-order approximation, close for a
// small effect.
TEST(ScoreCandidates, IsTheChiSquareARefitRemoves) {
  const SimulatedData data = Simulate("bias_drift_x=0.1,angle_offset=0.0005", 11);
  const JointData prepared(data.test, data.run, data.conditions, data.landmarks);
  const JointOptions options = StatedNoise(data.conditions);
  JointResult baseline;
  ASSERT_TRUE(SolveJoint(prepared, options, &baseline).ok());
  const std::vector<Parameter> candidates = {Parameter::kBiasDriftX, Parameter::kAngleOffset,
                                             Parameter::kBiasDriftY};
  std::vector<double> scores;
  ASSERT_TRUE(ScoreCandidates(prepared, options, baseline, candidates, &scores).ok());
  ASSERT_EQ(scores.size(), candidates.size());
  const double baseline_chi2 = baseline.chi2_x + baseline.chi2_y;
  for (size_t c = 0; c < candidates.size(); ++c) {
    JointOptions extended = options;
    extended.effects = {candidates[c]};
    JointResult refit;
    ASSERT_TRUE(SolveJoint(prepared, extended, &refit).ok());
    const double removed = baseline_chi2 - (refit.chi2_x + refit.chi2_y);
    const char* name = Info(candidates[c]).name;
    if (candidates[c] == Parameter::kAngleOffset) {
      EXPECT_NEAR(scores[c], removed, 0.02 * removed + 0.05) << name;
    } else {
      EXPECT_NEAR(scores[c], removed, 1e-6 * removed + 1e-6) << name;
    }
  }
  // The hidden drift is visible, the absent one is not (chi-square(1) under the null).
  EXPECT_GT(scores[0], 30.0);
  EXPECT_LT(scores[2], 15.0);
}

TEST(CheckIdentifiable, NamesTheParametersOfANearNullDirection) {
  const std::vector<Parameter> parameters = {Parameter::kBiasX, Parameter::kScaleX,
                                             Parameter::kBiasDriftX};
  // Columns: bias, scale and a third equal to 2 x bias: the third and the first move together.
  Eigen::MatrixXd jacobian(6, 3);
  jacobian << 1, 0.3, 2, 1, -0.8, 2, 1, 0.1, 2, 1, 0.9, 2, 1, -0.2, 2, 1, 0.5, 2;
  const Status status =
      CheckIdentifiable(jacobian.transpose() * jacobian, parameters, /*threshold=*/1e-10);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("bias_x"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("bias_drift_x"), std::string::npos) << status.message();
  EXPECT_EQ(status.message().find("scale_x"), std::string::npos) << status.message();

  // A parameter nothing depends on is named as such.
  jacobian.col(2).setZero();
  const Status unconstrained =
      CheckIdentifiable(jacobian.transpose() * jacobian, parameters, 1e-10);
  ASSERT_FALSE(unconstrained.ok());
  EXPECT_NE(unconstrained.message().find("no residual depends on bias_drift_x"), std::string::npos)
      << unconstrained.message();

  // Separable columns pass, however different their scales.
  jacobian.col(2) << 1e-3, -2e-3, 0.5e-3, 0, 1e-3, 3e-3;
  EXPECT_TRUE(CheckIdentifiable(jacobian.transpose() * jacobian, parameters, 1e-10).ok());
}

TEST(ParseEffects, AcceptsTheCatalogueByNameEachOnce) {
  const std::vector<Parameter> all = EstimableEffects();
  std::vector<Parameter> effects;
  ASSERT_TRUE(ParseEffects("all", &effects).ok());
  EXPECT_EQ(effects, all);
  // "all" beside a named effect lists it once, wherever it appears.
  ASSERT_TRUE(ParseEffects("angle_offset,all", &effects).ok());
  EXPECT_EQ(std::set<Parameter>(effects.begin(), effects.end()).size(), effects.size());
  EXPECT_EQ(effects.size(), all.size());
  ASSERT_TRUE(ParseEffects("all,angle_offset", &effects).ok());
  EXPECT_EQ(effects, all);
  ASSERT_TRUE(ParseEffects("nonorthogonality,angle_offset,nonorthogonality", &effects).ok());
  EXPECT_EQ(effects,
            (std::vector<Parameter>{Parameter::kNonorthogonality, Parameter::kAngleOffset}));
  ASSERT_TRUE(ParseEffects("none", &effects).ok());
  EXPECT_TRUE(effects.empty());

  // Every estimable effect of the catalogue, and nothing else, is offered by name.
  for (const ParameterInfo& info : ParameterCatalogue()) {
    const bool estimable = !info.baseline && !IsNoiseRatio(info.parameter);
    EXPECT_EQ(ParseEffects(info.name, &effects).ok(), estimable) << info.name;
    EXPECT_EQ(EstimableEffectNames().find(info.name) != std::string::npos, estimable) << info.name;
  }
  const Status unknown = ParseEffects("angle_ofset", &effects);
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.message().find(EstimableEffectNames()), std::string::npos);
}

TEST(RobustLoss, NamesRoundTripAndATypoIsAnError) {
  for (const RobustLoss loss : {RobustLoss::kNone, RobustLoss::kHuber, RobustLoss::kCauchy}) {
    RobustLoss parsed = loss == RobustLoss::kNone ? RobustLoss::kHuber : RobustLoss::kNone;
    ASSERT_TRUE(ParseRobustLoss(RobustLossName(loss), &parsed).ok()) << RobustLossName(loss);
    EXPECT_EQ(parsed, loss);
  }
  RobustLoss parsed = RobustLoss::kNone;
  const Status typo = ParseRobustLoss("hubber", &parsed);
  ASSERT_FALSE(typo.ok());
  EXPECT_NE(typo.message().find("hubber"), std::string::npos);
}

}  // namespace
}  // namespace accelcal
