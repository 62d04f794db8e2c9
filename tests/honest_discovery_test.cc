// Discovery on data whose cause is outside the catalogue (issue 16): correlated noise,
// outliers, heavy tails, a shape in theta no effect has, a step in the test. Each class
// is hidden at about 10 sigma of its signature (the chi-square it would remove from the
// baseline, or the noise statistic's z), in 50 seeds; the honest verdict (the class named,
// no catalogue effect claimed as the whole cause) must come in at least 90% of them.
// A smaller test design (4000 samples) keeps the suite fast; the shapes are scaled so
// that their signature stays at about 10 sigma.

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "estimation/statistics/noise_analysis.h"
#include "estimation/tilt_table/discovery.h"
#include "io/scenario_json.h"
#include "models/noise_model.h"
#include "simulation/random.h"
#include "simulation/scenario.h"

namespace accelcal {
namespace {

constexpr int kSeeds = 50;

Scenario ScenarioWith(const std::string& assignments) {
  Scenario scenario;
  EXPECT_TRUE(LoadDefaultScenario(&scenario).ok());
  EXPECT_TRUE(ApplyScenarioOverrides("tilt_samples=4000," + assignments, &scenario).ok());
  return scenario;
}

DiscoveryResult DiscoverIn(const Scenario& scenario, uint64_t seed) {
  const SimulatedData data = SimulateScenario(scenario, seed);
  DiscoveryOptions options;
  DiscoveryResult result;
  const Status status =
      Discover(data.test, data.run, data.conditions, data.landmarks, options, &result);
  EXPECT_TRUE(status.ok()) << status.message();
  return result;
}

bool NamesCatalogueEffect(const DiscoveryResult& result) {
  for (const DiscoveredEffect& effect : result.effects) {
    if (!IsNoiseRatio(effect.effect)) return true;
  }
  return false;
}

bool Finds(const DiscoveryResult& result, NoiseFinding::Kind kind) {
  for (const NoiseFinding& finding : result.noise_findings) {
    if (finding.kind == kind) return true;
  }
  return false;
}

struct ClassCase {
  const char* id;  // the test's name
  const char* name;
  const char* assignments;
  // Honest: the class named and no catalogue effect claimed as the whole cause.
  bool (*honest)(const DiscoveryResult&);
};

// N = 4000, sigma_x = 0.5: a shape of amplitude a on x has signature N a^2 / (2 sigma^2)
// once the baseline has taken its share; a = 0.11 gives about 100 for a 2-theta harmonic.
const ClassCase kClasses[] = {
    {"CorrelatedNoise", "correlated noise", "noise_ar1_x=0.6,noise_ar1_y=0.6",
     [](const DiscoveryResult& r) {
       return Finds(r, NoiseFinding::Kind::kCorrelation) && !NamesCatalogueEffect(r);
     }},
    {"WeaklyCorrelatedNoise", "weakly correlated noise (10 sigma of the lag-1 test)",
     "noise_ar1_x=0.22",
     [](const DiscoveryResult& r) {
       return Finds(r, NoiseFinding::Kind::kCorrelation) && !NamesCatalogueEffect(r);
     }},
    {"Outliers", "outliers", "outlier_fraction=0.01,outlier_sigma=12",
     [](const DiscoveryResult& r) {
       return Finds(r, NoiseFinding::Kind::kOutliers) && !NamesCatalogueEffect(r);
     }},
    // Enough large outliers to carry least squares' bias, and the run, to another landmark.
    {"ManyLargeOutliers", "outliers, 5% at 50 sigma", "outlier_fraction=0.05,outlier_sigma=50",
     [](const DiscoveryResult& r) {
       return Finds(r, NoiseFinding::Kind::kOutliers) && !NamesCatalogueEffect(r);
     }},
    {"HeavyTails", "heavy tails", "noise_student_t_dof=3",
     [](const DiscoveryResult& r) {
       return Finds(r, NoiseFinding::Kind::kHeavyTails) && !NamesCatalogueEffect(r);
     }},
    {"ThetaHarmonic", "a 2-theta harmonic", "theta_harmonic_order=2,theta_harmonic_x=0.11",
     [](const DiscoveryResult& r) { return r.verdict_code == Verdict::kUnexplained; }},
    {"CubicScale", "a cubic scale term (a 3-theta shape)", "scale_cubic_x=0.00047",
     [](const DiscoveryResult& r) { return r.verdict_code == Verdict::kUnexplained; }},
    {"StepInTheMiddle", "a step in the middle of the test", "bias_step_at=0.5,bias_step_x=0.36",
     [](const DiscoveryResult& r) { return r.verdict_code == Verdict::kUnexplained; }},
    // After the baseline, a step at 30% of the sweep keeps sum r^2 = 493 of its unit shape.
    {"StepAtThirtyPercent", "a step at 30% of the test", "bias_step_at=0.3,bias_step_x=0.225",
     [](const DiscoveryResult& r) { return r.verdict_code == Verdict::kUnexplained; }},
};

void PrintTo(const ClassCase& c, std::ostream* os) { *os << c.name; }

class HonestVerdictTest : public testing::TestWithParam<ClassCase> {};

TEST_P(HonestVerdictTest, ComesInAtLeastNinetyPercentOfSeeds) {
  const ClassCase& c = GetParam();
  const Scenario scenario = ScenarioWith(c.assignments);
  int honest = 0;
  std::string example;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const DiscoveryResult result = DiscoverIn(scenario, seed);
    if (c.honest(result)) {
      ++honest;
    } else if (example.empty()) {
      example = "seed " + std::to_string(seed) + ": " + result.verdict;
    }
  }
  std::printf("%s: honest verdict in %d of %d seeds\n", c.name, honest, kSeeds);
  EXPECT_GE(honest, 0.9 * kSeeds) << c.name << "; first miss, " << example;
}

INSTANTIATE_TEST_SUITE_P(OutsideTheCatalogue, HonestVerdictTest, testing::ValuesIn(kClasses),
                         [](const testing::TestParamInfo<ClassCase>& info) {
                           return std::string(info.param.id);
                         });

// Two catalogue effects the data cannot tell apart: with the x axis 100 times noisier
// than y, the angle offset and the non-orthogonality both show only as a sin(theta) term
// on y (their x signatures are buried), and the run is not tied to a landmark it could
// separate them with well. The verdict must say so, with both estimates.
TEST(Ambiguity, TwoEffectsTheDataCannotSeparateAreReportedAsSuch) {
  const Scenario scenario = ScenarioWith("noise_variance_x_stated=100,angle_offset=0.02");
  int ambiguous = 0;
  for (int seed = 1; seed <= 10; ++seed) {
    const DiscoveryResult result = DiscoverIn(scenario, seed);
    bool pair = false;
    for (const Ambiguity& ambiguity : result.ambiguities) {
      for (const Ambiguity::Alternative& alternative : ambiguity.alternatives) {
        const std::set<std::string> names = {Info(ambiguity.effect).name,
                                             Info(alternative.effect).name};
        pair |= names == std::set<std::string>{"angle_offset", "nonorthogonality"} &&
                !ambiguity.separation.empty();
      }
    }
    ambiguous += result.verdict_code == Verdict::kCannotTellApart && pair;
  }
  EXPECT_GE(ambiguous, 8);
}

// Over half a circle, a 3-theta harmonic on x and scale_nonlinearity_x are nearly the same
// shape: the catalogue effect fits it, and the checks of the final model see nothing. The
// answer must not be "missing: scale_nonlinearity_x" alone: either the shape is named as
// an alternative the design cannot tell apart, or structure remains.
TEST(Ambiguity, AShapeOutsideTheCatalogueThatACatalogueEffectMimicsIsNamedAsAnAlternative) {
  Scenario scenario = ScenarioWith("theta_harmonic_order=3,theta_harmonic_x=0.12");
  scenario.tilt.kind = TiltSchedule::Kind::kUniform;
  scenario.tilt.sample_count = 2000;
  scenario.tilt.theta_begin_rad = 0.0;
  scenario.tilt.theta_end_rad = M_PI;
  int honest = 0;
  std::string example;
  for (int seed = 1; seed <= 20; ++seed) {
    const DiscoveryResult result = DiscoverIn(scenario, seed);
    bool shape_named = result.verdict_code == Verdict::kUnexplained;
    for (const Ambiguity& ambiguity : result.ambiguities) {
      for (const Ambiguity::Alternative& alternative : ambiguity.alternatives)
        shape_named |= alternative.shape == "x: 3-theta harmonic";
    }
    honest += shape_named;
    if (!shape_named && example.empty()) example = result.verdict;
  }
  EXPECT_GE(honest, 18) << example;
}

// With AR(1) noise the reported sigma of bias and scale must match their Monte Carlo
// spread (within 15%): the whitening carries the correlation into the covariance. The
// white-noise fit of the same data reports sigmas about sqrt((1 + rho) / (1 - rho)) = 2
// times too small, which this test would catch.
// The run ends among decoys at least 400 m apart, so the tie is the true landmark in every
// trial (with the course's landmarks 100 m apart, a trial tied to a neighbour would add the
// landmark choice to the spread).
TEST(CorrelatedNoise, ReportedSigmasMatchTheMonteCarloSpread) {
  Scenario scenario = ScenarioWith("noise_ar1_x=0.6,noise_ar1_y=0.6");
  scenario.landmarks = LandmarkSpec();
  scenario.landmarks.decoys = true;
  scenario.landmarks.decoy_count = 3;
  scenario.landmarks.decoy_min_distance_m = 400.0;
  const Parameter parameters[4] = {Parameter::kBiasX, Parameter::kScaleX, Parameter::kBiasY,
                                   Parameter::kScaleY};
  constexpr int kTrials = 150;
  double sum[4] = {}, sum2[4] = {}, reported[4] = {};
  for (int seed = 1; seed <= kTrials; ++seed) {
    const DiscoveryResult result = DiscoverIn(scenario, 1000 + seed);
    for (int p = 0; p < 4; ++p) {
      const double value = result.extended.estimate.Value(parameters[p]);
      sum[p] += value;
      sum2[p] += value * value;
      reported[p] += result.extended.estimate.StandardDeviation(parameters[p]);
    }
  }
  for (int p = 0; p < 4; ++p) {
    const double mean = sum[p] / kTrials;
    const double spread = std::sqrt((sum2[p] / kTrials - mean * mean) * kTrials / (kTrials - 1));
    const double sigma = reported[p] / kTrials;
    std::printf("%s: Monte Carlo spread %.4g, mean reported sigma %.4g (ratio %.3f)\n",
                Info(parameters[p]).name, spread, sigma, sigma / spread);
    // 150 trials: the spread's own relative sd is about 6%.
    EXPECT_NEAR(sigma / spread, 1.0, 0.15) << Info(parameters[p]).name;
  }
}

// With Student-t noise (3 dof) discovery fits the final model with a Huber loss; its
// sandwich covariance must match the Monte Carlo spread of the Huber estimates (within 15%),
// and the Huber estimates must be more precise than least squares' (whose spread is the
// stated sigma's, since the noise has the stated variance).
TEST(HeavyTails, TheRobustFitsSigmasMatchTheMonteCarloSpread) {
  Scenario scenario = ScenarioWith("noise_student_t_dof=3");
  scenario.landmarks = LandmarkSpec();
  scenario.landmarks.decoys = true;
  scenario.landmarks.decoy_count = 3;
  scenario.landmarks.decoy_min_distance_m = 400.0;
  const Parameter parameters[4] = {Parameter::kBiasX, Parameter::kScaleX, Parameter::kBiasY,
                                   Parameter::kScaleY};
  constexpr int kTrials = 150;
  double sum[4] = {}, sum2[4] = {}, reported[4] = {}, least_squares[4] = {};
  int robust = 0;
  for (int seed = 1; seed <= kTrials; ++seed) {
    const DiscoveryResult result = DiscoverIn(scenario, 2000 + seed);
    robust += result.robust_fit;
    for (int p = 0; p < 4; ++p) {
      const double value = result.extended.estimate.Value(parameters[p]);
      sum[p] += value;
      sum2[p] += value * value;
      reported[p] += result.extended.estimate.StandardDeviation(parameters[p]);
      least_squares[p] += std::sqrt(result.baseline.covariance(p, p));
    }
  }
  EXPECT_GE(robust, 0.9 * kTrials);
  for (int p = 0; p < 4; ++p) {
    const double mean = sum[p] / kTrials;
    const double spread = std::sqrt((sum2[p] / kTrials - mean * mean) * kTrials / (kTrials - 1));
    const double sigma = reported[p] / kTrials;
    std::printf(
        "%s: Monte Carlo spread %.4g, mean sandwich sigma %.4g (ratio %.3f); least "
        "squares sigma %.4g\n",
        Info(parameters[p]).name, spread, sigma, sigma / spread, least_squares[p] / kTrials);
    EXPECT_NEAR(sigma / spread, 1.0, 0.15) << Info(parameters[p]).name;
    EXPECT_LT(spread, least_squares[p] / kTrials) << Info(parameters[p]).name;
  }
}

// The noise analysis's level and correlation: calibrated under white noise (z about
// N(0, 1)) and unbiased under AR(1) noise, where the von Neumann ratio alone is 1 - rho.
TEST(NoiseAnalysis, ReadsCorrelationAndLevelApartAndIsCalibrated) {
  constexpr int kN = 4000;
  constexpr int kTrials = 400;
  for (const double rho : {0.0, 0.6}) {
    double z_level2 = 0.0, z_corr2 = 0.0, ratio = 0.0, corr = 0.0, ratio_sd = 0.0;
    for (int t = 0; t < kTrials; ++t) {
      RandomSource random(77, t);
      std::vector<double> e(kN);
      double previous = random.StandardNormal();
      e[0] = previous;
      for (int i = 1; i < kN; ++i) {
        previous = rho * previous + std::sqrt(1 - rho * rho) * random.StandardNormal();
        e[i] = previous;
      }
      const NoiseAnalysis a = AnalyzeNoise(e, 1.0, {}, false);
      z_level2 += a.level_z * a.level_z;
      z_corr2 += a.correlation_z * a.correlation_z;
      ratio += a.variance_ratio;
      corr += a.correlation;
      ratio_sd += a.variance_ratio_stddev;
    }
    ratio /= kTrials;
    corr /= kTrials;
    EXPECT_NEAR(ratio, 1.0, 4 * ratio_sd / kTrials / std::sqrt(1.0 / kTrials)) << rho;
    EXPECT_NEAR(corr, rho, 0.01) << rho;
    // The level's z is N(0, 1) under the statement, at either correlation.
    EXPECT_NEAR(z_level2 / kTrials, 1.0, 0.25) << rho;
    if (rho == 0.0) EXPECT_NEAR(z_corr2 / kTrials, 1.0, 0.25);
  }
}

}  // namespace
}  // namespace accelcal
