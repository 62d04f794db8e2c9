// Discovery at its edges on the triad (issue 33, item 2): two effects of the catalogue present
// together, each about 6 sigma alone but correlated in the design, must not come out as one
// effect carrying the other's signal. The design: 40 random directions held in the order of
// their n_x^2 (with a little disorder), so that an offset drift of x (linear in time) and a
// quadratic scale term of x (n_x^2 on x) look alike; each hidden at 6 sigma of its own fit alone.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "estimation/triad/triad_discovery.h"
#include "simulation/random.h"
#include "simulation/triad_simulator.h"
#include "studies/triad_monte_carlo.h"
#include "triad_test_session.h"

namespace accelcal {
namespace {

TriadSimulationOptions Session() { return testing::TriadTestSimulationOptions(); }

TriadDiscoveryOptions Discovery() { return testing::TriadTestDiscovery(0.01); }

// 40 random directions held in the order of n_x^2 plus a little noise.
std::vector<std::array<double, 3>> OrderedByXSquared(RandomSource* random) {
  std::vector<std::array<double, 3>> directions = RandomPoseDirections(40, random);
  std::vector<std::pair<double, std::array<double, 3>>> keyed;
  for (const auto& n : directions)
    keyed.push_back({n[0] * n[0] + 0.3 * random->StandardNormal(), n});
  std::sort(keyed.begin(), keyed.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (size_t i = 0; i < keyed.size(); ++i) directions[i] = keyed[i].second;
  return directions;
}

std::vector<TriadPoseMean> SimulateWith(const TriadEffectCoefficients& effects, uint64_t seed) {
  RandomSource random(500 + seed, 3);
  TriadSimulationOptions session = Session();
  session.effects = effects;
  return SimulateTriadPoses(session, OrderedByXSquared(&random), &random);
}

TEST(TriadPartners, TwoCorrelatedEffectsAreNotReportedAsOneCarryingTheOthersSignal) {
  const int drift = TriadEffectCoefficientIndex("offset_drift_x");
  const int k2 = TriadEffectCoefficientIndex("scale_nonlinearity_x");
  // Each effect's sigma alone, and together, on a null session of the design.
  const std::vector<TriadPoseMean> null = SimulateWith({}, 0);
  double alone[2], together[2];
  for (int i = 0; i < 2; ++i) {
    TriadMlOptions fit = Discovery().fit;
    fit.effects = {i == 0 ? drift : k2};
    TriadMlResult result;
    ASSERT_TRUE(CalibrateTriadMl(null, fit, &result).ok());
    alone[i] = result.effects_stddev[i == 0 ? drift : k2];
  }
  {
    TriadMlOptions fit = Discovery().fit;
    fit.effects = {drift, k2};
    TriadMlResult result;
    ASSERT_TRUE(CalibrateTriadMl(null, fit, &result).ok());
    together[0] = result.effects_stddev[drift];
    together[1] = result.effects_stddev[k2];
  }
  const double truth[2] = {6.0 * alone[0], 6.0 * alone[1]};
  std::printf(
      "offset_drift_x = %.3g (sigma %.3g alone, %.3g beside), scale_nonlinearity_x = %.3g "
      "(sigma %.3g alone, %.3g beside)\n",
      truth[0], alone[0], together[0], truth[1], alone[1], together[1]);
  // The design does make them look alike: each under 4.5 sigma once the other is fitted.
  EXPECT_LT(truth[0] / together[0], 4.5);
  EXPECT_LT(truth[1] / together[1], 4.5);

  TriadEffectCoefficients hidden{};
  hidden[drift] = truth[0];
  hidden[k2] = truth[1];
  int single = 0, both = 0, doubted = 0;
  std::string example;
  for (uint64_t seed = 1; seed <= 50; ++seed) {
    TriadDiscoveryResult result;
    ASSERT_TRUE(DiscoverTriad(SimulateWith(hidden, seed), Discovery(), &result).ok());
    int named = 0;
    for (const TriadFoundEffect& effect : result.effects)
      named += effect.coefficient == drift || effect.coefficient == k2;
    both += named == 2;
    doubted += result.verdict_code == Verdict::kCannotTellApart;
    // Reported with its partner (or a swap with it): the doubt is in the verdict.
    bool paired = false;
    for (const TriadAmbiguity& ambiguity : result.ambiguities)
      paired = paired || ambiguity.alternative.find("offset_drift_x") != std::string::npos ||
               ambiguity.alternative.find("scale_nonlinearity_x") != std::string::npos;
    if (named != 1 || paired) continue;
    // One of the two named alone, with a confident verdict: its estimate must not carry the
    // other's signal (3 sigma from its own truth).
    for (const TriadFoundEffect& effect : result.effects) {
      const int i = effect.coefficient == drift ? 0 : (effect.coefficient == k2 ? 1 : -1);
      if (i < 0) continue;
      if (std::abs(effect.estimate - truth[i]) > 3.0 * effect.stddev) {
        ++single;
        if (example.empty()) example = "seed " + std::to_string(seed) + ": " + result.verdict;
      }
    }
  }
  std::printf(
      "of 50 seeds: both named %d, cannot tell apart %d, one named alone carrying the "
      "other's signal %d\n",
      both, doubted, single);
  EXPECT_EQ(single, 0) << example;
}

// The price, on the same design: one of the two hidden alone at 6 sigma. The data cannot always
// say the other is absent; the effect must still be named (alone, or with the doubt), and its
// estimate stay within 3 sigma of its truth when named alone.
TEST(TriadPartners, OneEffectOfTheDesignAloneIsStillNamed) {
  const int drift = TriadEffectCoefficientIndex("offset_drift_x");
  const int k2 = TriadEffectCoefficientIndex("scale_nonlinearity_x");
  for (const int hidden_one : {drift, k2}) {
    TriadMlOptions fit = Discovery().fit;
    fit.effects = {hidden_one};
    TriadMlResult alone;
    ASSERT_TRUE(CalibrateTriadMl(SimulateWith({}, 0), fit, &alone).ok());
    TriadEffectCoefficients hidden{};
    hidden[hidden_one] = 6.0 * alone.effects_stddev[hidden_one];
    int named = 0, doubted = 0, off = 0;
    for (uint64_t seed = 1; seed <= 50; ++seed) {
      TriadDiscoveryResult result;
      ASSERT_TRUE(DiscoverTriad(SimulateWith(hidden, seed), Discovery(), &result).ok());
      doubted += result.verdict_code == Verdict::kCannotTellApart;
      for (const TriadFoundEffect& effect : result.effects) {
        if (effect.coefficient != hidden_one) continue;
        ++named;
        off += result.verdict_code != Verdict::kCannotTellApart &&
               std::abs(effect.estimate - hidden[hidden_one]) > 3.0 * effect.stddev;
      }
    }
    std::printf(
        "%s alone: named in %d of 50, cannot tell apart in %d, named alone 3 sigma off "
        "%d\n",
        TriadEffectCoefficientList()[hidden_one].name.c_str(), named, doubted, off);
    EXPECT_GE(named, 45);
    EXPECT_LE(off, 2);
  }
}

// Held out from the design above: other axes, other pose counts, other seeds, the poses held in
// the order of n_k^2 (with the same disorder), offset_drift_k and scale_nonlinearity_k each 6
// sigma alone (3.7 to 4.3 sigma beside the other). Every effect named alone with a confident
// verdict is counted when 3 sigma or more from its truth. Measured: 0 of 150; 1 of 150 without
// the reach rule (n_x^2, 60 poses). Over seeds 1-100 of each design, 2 of 300 with the rule
// (noise draws that hide the partner: in one, the fit with both effects is itself 3 sigma from
// the truth and the partner beside the one named gains p = 0.21), 6 of 300 without.
TEST(TriadPartners, AcrossDesignsNoEffectIsNamedAloneCarryingTheOthersSignal) {
  struct Design {
    int axis;
    int poses;
  };
  int single = 0, total = 0;
  for (const Design design : {Design{1, 40}, Design{2, 30}, Design{0, 60}}) {
    const std::string axis(1, "xyz"[design.axis]);
    const int drift = TriadEffectCoefficientIndex("offset_drift_" + axis);
    const int k2 = TriadEffectCoefficientIndex("scale_nonlinearity_" + axis);
    const auto simulate = [&](const TriadEffectCoefficients& effects, uint64_t seed) {
      RandomSource random(900 + seed, 3);
      std::vector<std::array<double, 3>> directions = RandomPoseDirections(design.poses, &random);
      std::vector<std::pair<double, std::array<double, 3>>> keyed;
      for (const auto& n : directions)
        keyed.push_back({n[design.axis] * n[design.axis] + 0.3 * random.StandardNormal(), n});
      std::sort(keyed.begin(), keyed.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
      for (size_t i = 0; i < keyed.size(); ++i) directions[i] = keyed[i].second;
      TriadSimulationOptions session = Session();
      session.effects = effects;
      return SimulateTriadPoses(session, directions, &random);
    };
    TriadEffectCoefficients hidden{};
    for (const int c : {drift, k2}) {
      TriadMlOptions fit = Discovery().fit;
      fit.effects = {c};
      TriadMlResult alone;
      ASSERT_TRUE(CalibrateTriadMl(simulate({}, 0), fit, &alone).ok());
      hidden[c] = 6.0 * alone.effects_stddev[c];
    }
    int here = 0;
    for (uint64_t seed = 1; seed <= 50; ++seed) {
      TriadDiscoveryResult result;
      ASSERT_TRUE(DiscoverTriad(simulate(hidden, seed), Discovery(), &result).ok());
      ++total;
      int named = 0;
      for (const TriadFoundEffect& effect : result.effects)
        named += effect.coefficient == drift || effect.coefficient == k2;
      if (named != 1 || !result.ambiguities.empty()) continue;
      for (const TriadFoundEffect& effect : result.effects) {
        if ((effect.coefficient == drift || effect.coefficient == k2) &&
            std::abs(effect.estimate - hidden[effect.coefficient]) > 3.0 * effect.stddev) {
          ++here;
          std::printf("  n_%s^2, %d poses, seed %d: %s\n", axis.c_str(), design.poses,
                      static_cast<int>(seed), result.verdict.c_str());
        }
      }
    }
    std::printf("n_%s^2, %d poses: one named alone carrying the other's signal in %d of 50\n",
                axis.c_str(), design.poses, here);
    single += here;
  }
  EXPECT_EQ(single, 0) << "of " << total;
}

}  // namespace
}  // namespace accelcal
