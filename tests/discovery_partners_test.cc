// Discovery at its edges (issue 33, item 2): two effects of the catalogue present together, each
// about 6 sigma alone but correlated in the design (each about 3.6 sigma once the other is
// fitted), must not come out as one effect carrying the other's signal. The design: the course's
// tilt test over 0 to 4.4 rad, where angle_offset (cos theta on x) and bias_drift_x (linear in
// the sample's place, so in theta) correlate at 0.80; angle_offset = 0.0029 rad and
// bias_drift_x = 0.103 m/s^2, each 6 sigma alone. Before FindPartners, 18 of 50 seeds named one
// of them without the other, 3 to 6 sigma from its truth.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "discovery_seed.h"
#include "estimation/tilt_table/discovery.h"
#include "io/scenario_json.h"
#include "models/effects.h"
#include "simulation/scenario.h"

namespace accelcal {
namespace {

Scenario CorrelatedDesign(const std::string& hidden) {
  Scenario scenario;
  EXPECT_TRUE(LoadDefaultScenario(&scenario).ok());
  EXPECT_TRUE(ApplyScenarioOverrides(hidden, &scenario).ok());
  scenario.tilt.sample_count = 20001;
  scenario.tilt.theta_begin_rad = 0.0;
  scenario.tilt.theta_end_rad = 4.4;
  return scenario;
}

bool HasPartner(const DiscoveryResult& result) {
  for (const Ambiguity& ambiguity : result.ambiguities) {
    for (const Ambiguity::Alternative& alternative : ambiguity.alternatives)
      if (alternative.beside) return true;
  }
  return false;
}

// A partner in another effect's place (a look-alike of the design that moves an effect kept).
bool HasPartnerInstead(const DiscoveryResult& result) {
  for (const Ambiguity& ambiguity : result.ambiguities) {
    for (const Ambiguity::Alternative& alternative : ambiguity.alternatives)
      if (alternative.replaces) return true;
  }
  return false;
}

TEST(DiscoveryPartners, TwoCorrelatedEffectsAreNotReportedAsOneCarryingTheOthersSignal) {
  const std::map<std::string, double> truth = {{"angle_offset", 0.0029}, {"bias_drift_x", 0.103}};
  const Scenario scenario = CorrelatedDesign("angle_offset=0.0029,bias_drift_x=0.103");
  int single = 0, with_partner = 0;
  for (uint64_t seed = 1; seed <= 50; ++seed) {
    const DiscoveryResult result = DiscoverSeed(SimulateScenario(scenario, seed));
    with_partner += HasPartner(result);
    int named = 0;
    for (const DiscoveredEffect& effect : result.effects)
      named += truth.count(Info(effect.effect).name);
    if (named != 1 || result.verdict_code == Verdict::kCannotTellApart) continue;
    // One of the two named alone, with a confident verdict: its estimate must not carry the
    // other's signal (3 sigma from its own truth).
    for (const DiscoveredEffect& effect : result.effects) {
      const auto t = truth.find(Info(effect.effect).name);
      if (t == truth.end()) continue;
      const double z = (effect.estimate - t->second) / effect.stddev;
      if (std::abs(z) > 3.0) {
        ++single;
        std::printf("seed %d: %s alone, %.1f sigma from its truth: %s\n", static_cast<int>(seed),
                    t->first.c_str(), z, result.verdict.c_str());
      }
    }
  }
  // Measured: 0 of 50; 18 of 50 before partners beside an effect, 1 of 50 before partners in
  // another's place (seed 6 named bias_drift_x = 0.172 +- 0.017 with nonorthogonality, which
  // took the y part of angle_offset's signal; angle_offset in its place fits within delta chi2
  // 3.1 and gives bias_drift_x = 0.105). A partner is named in most seeds.
  EXPECT_EQ(single, 0);
  EXPECT_GE(with_partner, 25);
}

// Held out from the design above: the tilt over 0.5 to 3.0 rad only, where angle_offset and
// bias_drift_x correlate so closely (each 2.4 sigma once the other is fitted, 6 sigma alone)
// that the partner beside the one named seldom gains p <= 0.1: before the reach rule, 11 of 30
// seeds named one of them alone, 4.7 to 9 sigma from its truth.
TEST(DiscoveryPartners, TwoEffectsTheDesignBarelySeparatesAreNeverOneConfidentCause) {
  const std::map<std::string, double> truth = {{"angle_offset", 0.003425},
                                               {"bias_drift_x", 0.076248}};
  Scenario scenario = CorrelatedDesign("angle_offset=0.003425,bias_drift_x=0.076248");
  scenario.tilt.theta_begin_rad = 0.5;
  scenario.tilt.theta_end_rad = 3.0;
  int single = 0;
  for (uint64_t seed = 1; seed <= 30; ++seed) {
    const DiscoveryResult result = DiscoverSeed(SimulateScenario(scenario, seed));
    int named = 0;
    for (const DiscoveredEffect& effect : result.effects)
      named += truth.count(Info(effect.effect).name);
    if (named != 1 || result.verdict_code == Verdict::kCannotTellApart) continue;
    for (const DiscoveredEffect& effect : result.effects) {
      const auto t = truth.find(Info(effect.effect).name);
      if (t != truth.end() && std::abs(effect.estimate - t->second) > 3.0 * effect.stddev) {
        ++single;
        std::printf("seed %d: %s\n", static_cast<int>(seed), result.verdict.c_str());
      }
    }
  }
  EXPECT_EQ(single, 0);
}

TEST(DiscoveryPartners, TwoEffectsTheDesignSeparatesAreNotDoubtedByAPartnerInAnothersPlace) {
  // scale_nonlinearity_x and bias_drift_y, each about 8 sigma, on different axes: no effect of
  // the catalogue in one's place moves the other. Measured: both named (missing) in 25 of 30,
  // the other 5 doubted by look-alikes of bias_drift_y (nonorthogonality, a y harmonic) or
  // unexplained, the same with and without partners in another's place; a partner in another's
  // place in 0 of 30. (With nonorthogonality and bias_drift_x instead, 12 of 30 have one:
  // nonorthogonality and angle_offset look alike in this design, and every one of those 12 was
  // already doubted by that look-alike.)
  const Scenario scenario = CorrelatedDesign("scale_nonlinearity_x=0.0008,bias_drift_y=0.3");
  int both = 0, instead = 0;
  for (uint64_t seed = 1; seed <= 30; ++seed) {
    const DiscoveryResult result = DiscoverSeed(SimulateScenario(scenario, seed));
    int named = 0;
    for (const DiscoveredEffect& effect : result.effects)
      named += effect.effect == Parameter::kScaleNonlinearityX ||
               effect.effect == Parameter::kBiasDriftY;
    both += named == 2;
    instead += HasPartnerInstead(result);
  }
  std::printf("both named %d of 30, a partner in another's place %d\n", both, instead);
  EXPECT_GE(both, 27);
  EXPECT_LE(instead, 2);
}

TEST(DiscoveryPartners, OneEffectAloneIsRarelyGivenAPartner) {
  // angle_offset alone at 6 sigma: bias_drift_x beside it gains p <= 0.1 about 10% of the time
  // under the null, and then moves angle_offset by a sigma or more.
  const Scenario scenario = CorrelatedDesign("angle_offset=0.0029");
  int with_partner = 0, found = 0;
  for (uint64_t seed = 1; seed <= 50; ++seed) {
    const DiscoveryResult result = DiscoverSeed(SimulateScenario(scenario, seed));
    for (const DiscoveredEffect& effect : result.effects)
      found += effect.effect == Parameter::kAngleOffset;
    with_partner += HasPartner(result);
  }
  std::printf("found %d with partner %d\n", found, with_partner);
  EXPECT_GE(found, 45);
  // Measured: 3 of 50 by the gain alone (partner_alpha 0.1 with a 2 sigma shift: about 5%
  // expected), 9 of 50 with the reach rule: bias_drift_x beside it has r = 1.67, so one of its
  // sigmas beyond its estimate moves angle_offset by 3 sigma once |z| >= 1.24 (21% expected,
  // 10.7 of 50, sd 2.9). The price of never naming one of the pair alone.
  EXPECT_LE(with_partner, 17);
}

}  // namespace
}  // namespace accelcal
