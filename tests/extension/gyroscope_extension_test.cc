// The library built with one gyroscope effect of a research project's own (rate_cubic.h, one
// registration line in registered_gyroscope_effects.h): the effect reaches the registry, the
// simulator, the ML fit (its residuals' derivatives included) and discovery with no other change,
// and discovery names it when it is hidden in simulated turns and does not when nothing is.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "estimation/gyroscope/gyroscope_discovery.h"
#include "models/gyroscope_effect_list.h"
#include "rate_cubic.h"
#include "studies/gyroscope_monte_carlo.h"

namespace accelcal {
namespace {

constexpr int kCubic = GyroscopeEffectFirstOf<GyroscopeRateCubicEffect>();

TEST(ExtendedGyroscopeRegistry, AppendsTheNewEffectAfterTheBuiltInOnes) {
  EXPECT_EQ(GyroscopeEffectInfos().back().name, std::string("rate_cubic"));
  EXPECT_EQ(kCubic + 3, kGyroscopeEffectCoefficientCount);
  EXPECT_EQ(GyroscopeEffectCoefficientName(kCubic + 1), "gyroscope_rate_cubic_y");
  EXPECT_EQ(GyroscopeEffectCoefficientIndex("gyroscope_rate_cubic_z"), kCubic + 2);
  EXPECT_STREQ(GyroscopeEffectCoefficientUnit(kCubic), "1/(rad/s)^2");
  EXPECT_GE(GyroscopeEffectCoefficientIndex("gyroscope_time_offset"), 0);  // the built-in stay
}

// The composition and its inverse agree with the new term in: the simulator's output corrects
// back to the rate it was made from.
TEST(ExtendedGyroscopeRegistry, TheInverseUndoesTheCorrectionWithTheNewTerm) {
  GyroscopeEffectCoefficients effects{};
  effects[kCubic] = 2e-3;
  effects[kCubic + 1] = -3e-3;
  effects[kCubic + 2] = 1e-3;
  const GyroscopeParameters parameters = XsensLikeGyroscope();
  const GyroscopeOffset offset = XsensLikeGyroscopeOffset();
  const double force[3] = {0.3, -1.0, 9.7};
  for (const double scale : {-4.0, -0.5, 0.2, 3.0}) {
    const double rate[3] = {scale, -0.7 * scale, 0.4 * scale};
    double raw[3], back[3];
    GyroscopeRawWithEffects(parameters.data(), offset.data(), effects.data(), rate, force, raw);
    GyroscopeCorrectedRate(parameters.data(), offset.data(), effects.data(), raw, force, back);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], rate[k], 1e-12 * (1.0 + std::abs(scale)));
  }
}

// A session of the study's design with `cubic` times the effect's example hidden.
GyroscopeDiscoveryResult Discover(double cubic, uint64_t seed) {
  GyroscopeSessionDesign design;
  for (int k = 0; k < 3; ++k)
    design.effects[kCubic + k] = cubic * GyroscopeRateCubicEffect::kInfo.example[k];
  GyroscopeSessionFit fit;
  const Status status = SimulateAndCalibrateGyroscope(design, GyroscopeDesignHolds(design, seed),
                                                      seed * 7 + 1, {}, &fit);
  EXPECT_TRUE(status.ok()) << status.message();
  GyroscopeDiscoveryOptions options;
  options.alpha = 0.01;
  options.fit = fit.gyroscope_options;
  options.fit.effects.clear();
  GyroscopeDiscoveryResult result;
  const Status discovered =
      DiscoverGyroscope(fit.session.log, fit.intervals, fit.accelerometer_options,
                        fit.accelerometer, options, &result);
  EXPECT_TRUE(discovered.ok()) << discovered.message();
  return result;
}

TEST(RateCubic, DiscoveryNamesItWhenHiddenAndEstimatesItWithinThreeSigma) {
  const GyroscopeDiscoveryResult result = Discover(1.0, 5);
  ASSERT_EQ(result.effects.size(), 1u) << result.verdict;
  const GyroscopeFoundEffect& found = result.effects[0];
  EXPECT_EQ(found.effect, "rate_cubic");
  ASSERT_EQ(found.names.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(found.names[k], GyroscopeEffectCoefficientName(kCubic + k));
    const double truth = GyroscopeRateCubicEffect::kInfo.example[k];
    EXPECT_LT(std::abs(found.estimates[k] - truth), 3.0 * found.stddevs[k])
        << found.names[k] << " " << found.estimates[k] << " +- " << found.stddevs[k];
  }
}

TEST(RateCubic, DiscoveryFindsNothingWhenNothingIsHidden) {
  const GyroscopeDiscoveryResult result = Discover(0.0, 5);
  EXPECT_TRUE(result.effects.empty()) << result.verdict;
  bool scored = false;  // a candidate like the built-in ones
  for (const GyroscopeEffectScore& score : result.scores)
    scored = scored || score.effect == "rate_cubic";
  EXPECT_TRUE(scored);
}

}  // namespace
}  // namespace accelcal
