// The Earth's rate in the gyroscope's model (issue 44, item 3; docs/gyroscope.md, "The Earth's
// rate"): at rest a gyroscope turns with the Earth, Omega sin(latitude) about the up direction in
// every pose, the same pattern as a g-sensitivity G = (Omega sin(latitude) / g) I. On a quiet
// gyroscope (one pose mean's sigma 3e-5 rad/s, below the Earth's 7.29e-5) the vertical part is
// estimated within its sigma when the latitude is not given, and discovery does not name it as a
// g-sensitivity.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "estimation/gyroscope/gyroscope_ml_calibration.h"
#include "models/gyroscope.h"
#include "models/gyroscope_effect_list.h"
#include "residuals/gyroscope_residuals.h"
#include "studies/gyroscope_monte_carlo.h"

namespace accelcal {
namespace {

GyroscopeSessionDesign QuietGyroscopeOnTheEarth() {
  GyroscopeSessionDesign design;  // 30 poses of 4 s at 100 Hz, 3 counts: 3.2e-5 rad/s a pose
  design.earth_rate = true;
  design.latitude_deg = 59.35;
  return design;
}

// 200 sessions: the vertical rate's estimate about the truth, over its reported sigma, has
// mean within 0.25 and sd within [0.85, 1.15] (the sd's own sd is 5% at 200).
TEST(GyroscopeEarthRate, TheVerticalPartIsEstimatedWithinItsSigma) {
  const GyroscopeSessionDesign design = QuietGyroscopeOnTheEarth();
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 21);
  const double truth = kEarthRateRadPerS * std::sin(design.latitude_deg * M_PI / 180.0);
  const int sessions = 200;
  double sum = 0.0, squares = 0.0;
  for (int i = 0; i < sessions; ++i) {
    GyroscopeSessionFit fit;
    ASSERT_TRUE(SimulateAndCalibrateGyroscope(design, holds, 7000 + i, {}, &fit).ok());
    ASSERT_GT(fit.gyroscope.earth_vertical_rate_stddev, 0.0);
    const double z = (fit.gyroscope.earth_vertical_rate_rad_s - truth) /
                     fit.gyroscope.earth_vertical_rate_stddev;
    sum += z;
    squares += z * z;
  }
  const double mean = sum / sessions;
  const double sd = std::sqrt(squares / sessions - mean * mean);
  EXPECT_LT(std::abs(mean), 0.25);
  EXPECT_GT(sd, 0.85);
  EXPECT_LT(sd, 1.15);
}

// 200 sessions with discovery at alpha = 0.01, the latitude not given and given: g_sensitivity
// named at most as often as its own test's level allows on null sessions (alpha/2 + 2 sd: 3 of
// 200; measured 0 and 1), and the sessions not explained at most alpha + 2 sd (measured 1 and 1
// of 200). With the vertical part held at 0 instead, as before (the Earth's rate noise alone),
// g_sensitivity is named in most of them.
TEST(GyroscopeEarthRate, IsNeverNamedAsAGSensitivity) {
  for (bool known : {false, true}) {
    GyroscopeMonteCarloOptions options;
    options.design = QuietGyroscopeOnTheEarth();
    options.design.latitude_known = known;
    options.trials = 200;
    options.seed = known ? 31 : 30;
    options.discovery_alpha = 0.01;
    GyroscopeMonteCarloResult result;
    ASSERT_TRUE(RunGyroscopeMonteCarlo(options, &result).ok());
    ASSERT_EQ(result.succeeded, 200) << result.first_failure;
    EXPECT_LE(result.found[0], 200 * (0.005 + 2.0 * std::sqrt(0.005 * 0.995 / 200)))
        << "g_sensitivity named; latitude known: " << known;
    const int not_explained = 200 - result.verdicts[0];
    EXPECT_LE(not_explained, 200 * (0.01 + 2.0 * std::sqrt(0.01 * 0.99 / 200)))
        << "latitude known: " << known;
  }
}

// The vertical part is a registered effect of the gyroscope (models/gyroscope_effects/earth_rate.h)
// that discovery never tests and apply never applies. At rest the composition reads e n for an
// up direction n; through a turn it is invisible, as it must be (a rotation about gravity leaves
// gravity's direction in the body where it was): on a 90-degree turn about x with e in the rates
// and in the model, the turn's residual is the one with neither, to 1e-12, while a horizontal
// rate of the same size moves it by about e T.
TEST(GyroscopeEarthRate, IsAnEffectTheRestSeesAndTheTurnsCannot) {
  constexpr int kEarth = GyroscopeEffectFirstOf<GyroscopeEarthRateEffect>();
  const GyroscopeEffectInfo& info = GyroscopeEffectInfos()[GyroscopeEffectOf(kEarth)];
  EXPECT_EQ(std::string(info.name), "earth_rate");
  EXPECT_EQ(info.stage, GyroscopeEffectStage::kRate);
  EXPECT_NE(info.not_a_candidate, nullptr);
  EXPECT_NE(info.session_only, nullptr);
  GyroscopeParameters parameters =
      GyroscopeParametersWithGain(1.0 / 6000, 1.02 / 6000, 0.98 / 6000);
  parameters[kGyroscopeMisalignmentYz] = 0.01;
  parameters[kGyroscopeMisalignmentXy] = -0.02;
  const GyroscopeOffset offset = {12.0, -7.0, 3.0};
  const double e = 6.3e-5;
  GyroscopeEffectCoefficients earth{};
  earth[kEarth] = e;

  // At rest, up along (0.6, 0, 0.8).
  const double up[3] = {0.6, 0.0, 0.8};
  const double force[3] = {9.81 * up[0], 9.81 * up[1], 9.81 * up[2]};
  const double still[3] = {0.0, 0.0, 0.0};
  const double vertical[3] = {e * up[0], e * up[1], e * up[2]};
  double read[3], expected[3];
  GyroscopeRawWithEffects(parameters.data(), offset.data(), earth.data(), still, force, read);
  GyroscopeRawOutput(parameters.data(), offset.data(), vertical, expected);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(read[k], expected[k], 1e-9);
  EXPECT_GT(std::abs(read[0] - offset[0]), 0.2);  // e n_x / gain_x: 0.23 counts

  // A turn: pi/2 about x in 1.5 s at 100 Hz, from up = z.
  const double duration = 1.5, dt = 0.01, theta = M_PI / 2.0;
  const int count = static_cast<int>(std::lround(duration / dt)) + 1;
  std::vector<double> step_s(count - 1, dt);
  auto body_rate = [&](int j, double* rate) {
    rate[0] = theta * M_PI / (2.0 * duration) * std::sin(M_PI * j * dt / duration);
    rate[1] = rate[2] = 0.0;
  };
  double body_rotation[9];
  std::vector<std::array<double, 4>> path;
  IntegrateAngularRateHermite(count, body_rate, step_s, body_rotation, &path);
  const std::array<double, 3> before = {0.0, 0.0, 1.0};
  const std::array<double, 3> east = {1.0, 0.0, 0.0};  // a horizontal direction of the ground
  auto in_body = [&](int j, const std::array<double, 3>& ground) {
    double r[9];
    QuaternionToRotationMatrix(path[j].data(), r);
    return std::array<double, 3>{r[0] * ground[0] + r[3] * ground[1] + r[6] * ground[2],
                                 r[1] * ground[0] + r[4] * ground[1] + r[7] * ground[2],
                                 r[2] * ground[0] + r[5] * ground[1] + r[8] * ground[2]};
  };
  const std::array<double, 3> after = in_body(count - 1, before);
  // Its samples with the Earth's rate about up (or about east) added to the body's.
  auto turn = [&](const std::array<double, 3>& earth_axis, double size) {
    GyroscopeTurnSamples samples;
    samples.step_s = step_s;
    for (int j = 0; j < count; ++j) {
      double rate[3];
      body_rate(j, rate);
      const std::array<double, 3> n = in_body(j, before), a = in_body(j, earth_axis);
      for (int k = 0; k < 3; ++k) rate[k] += size * a[k];
      std::array<double, 3> raw;
      GyroscopeRawOutput(parameters.data(), offset.data(), rate, raw.data());
      samples.raw.push_back(raw);
      samples.specific_force.push_back({9.81 * n[0], 9.81 * n[1], 9.81 * n[2]});
    }
    return samples;
  };
  // E: two unit vectors normal to `after`.
  const std::array<std::array<double, 3>, 2> basis = {
      {{1.0, 0.0, 0.0}, {0.0, after[2], -after[1]}}};
  auto residual = [&](const GyroscopeTurnSamples& samples, const GyroscopeEffectCoefficients& c,
                      double* r) {
    GyroscopeTurnResidual turn_residual(samples, basis, {1.0, 0.0, 0.0, 1.0});
    const double* blocks[5] = {parameters.data(), offset.data(), c.data(), before.data(),
                               after.data()};
    ASSERT_TRUE(turn_residual.Evaluate(blocks, r, nullptr));
  };
  const GyroscopeEffectCoefficients none{};
  double plain[2], modelled[2], ignored[2], horizontal[2];
  residual(turn(before, 0.0), none, plain);
  residual(turn(before, e), earth, modelled);
  residual(turn(before, e), none, ignored);
  residual(turn(east, e), none, horizontal);
  for (int row = 0; row < 2; ++row) {
    EXPECT_NEAR(modelled[row], plain[row], 1e-12);
    EXPECT_NEAR(ignored[row], plain[row], 1e-12);
  }
  EXPECT_GT(std::hypot(horizontal[0] - plain[0], horizontal[1] - plain[1]), 0.5 * e * duration);
}

}  // namespace
}  // namespace accelcal
