// The library built with one triad effect of a research project's own (offset_warmup.h, one
// registration line in registered_triad_effects.h): the effect reaches the registry, the
// simulator, the ML fit and discovery with no other change (the one procedure,
// estimation/discovery/selection.h, takes it as a candidate), and discovery names it when it is
// hidden in simulated poses and does not when nothing is.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "estimation/triad/triad_discovery.h"
#include "models/triad_effect_list.h"
#include "offset_warmup.h"
#include "simulation/random.h"
#include "simulation/triad_simulator.h"
#include "studies/triad_monte_carlo.h"

namespace accelcal {
namespace {

constexpr double kGravity = 9.81744;

TEST(ExtendedTriadRegistry, AppendsTheNewEffectAfterTheBuiltInOnes) {
  const std::vector<TriadEffectCoefficient> list = TriadEffectCoefficientList();
  ASSERT_GE(list.size(), 3u);
  EXPECT_EQ(list[list.size() - 3].name, "offset_warmup_x");
  EXPECT_EQ(list.back().name, "offset_warmup_z");
  EXPECT_EQ(TriadEffectInfos().back().name, std::string("offset_warmup"));
  EXPECT_EQ(TriadEffectUnit(TriadEffectCoefficientIndex("offset_warmup_y"), "count"), "count/s^2");
  EXPECT_GE(TriadEffectCoefficientIndex("scale_nonlinearity_x"), 0);  // the built-in ones stay
}

// 40 poses 10 s apart in random directions, an Xsens-like triad, with `warmup_x` counts/s^2.
std::vector<TriadPoseMean> Session(double warmup_x, uint64_t seed) {
  TriadSimulationOptions options;
  options.truth = XsensLikeTriad();
  options.gravity_mps2 = kGravity;
  options.samples_per_pose = 100;
  options.noise_stddev = {3.0, 2.5, 3.5};
  options.pose_spacing_s = 10.0;
  options.effects[TriadEffectCoefficientIndex("offset_warmup_x")] = warmup_x;
  RandomSource random(seed);
  return SimulateTriadPoses(options, RandomPoseDirections(40, &random), &random);
}

TriadDiscoveryResult Discover(const std::vector<TriadPoseMean>& poses) {
  TriadDiscoveryOptions options;
  options.alpha = 0.01;
  options.fit.gravity_mps2 = kGravity;
  options.fit.initial = TriadStudyInitialGuess(XsensLikeTriad());
  options.cross_validation_folds = 0;
  TriadDiscoveryResult result;
  const Status status = DiscoverTriad(poses, options, &result);
  EXPECT_TRUE(status.ok()) << status.message();
  return result;
}

TEST(OffsetWarmup, DiscoveryNamesItWhenHiddenAndEstimatesItWithinThreeSigma) {
  // 1e-3 counts/s^2: 40 counts at the ends of a 390 s session, about its middle.
  const double truth = 1e-3;
  const TriadDiscoveryResult result = Discover(Session(truth, 7));
  ASSERT_EQ(result.verdict_code, Verdict::kMissing) << result.verdict;
  ASSERT_EQ(result.effects.size(), 1u) << result.verdict;
  EXPECT_EQ(result.effects[0].name, "offset_warmup_x");
  EXPECT_EQ(result.effects[0].unit, "count/s^2");
  EXPECT_LT(std::abs(result.effects[0].estimate - truth), 3.0 * result.effects[0].stddev)
      << result.effects[0].estimate << " +- " << result.effects[0].stddev;
}

TEST(OffsetWarmup, DiscoveryFindsNothingWhenNothingIsHidden) {
  const TriadDiscoveryResult result = Discover(Session(0.0, 7));
  EXPECT_EQ(result.verdict_code, Verdict::kExplained) << result.verdict;
  bool scored = false;  // a candidate like the built-in ones
  for (const TriadCandidateScore& score : result.candidates)
    scored = scored || score.name == "offset_warmup_x";
  EXPECT_TRUE(scored);
}

}  // namespace
}  // namespace accelcal
