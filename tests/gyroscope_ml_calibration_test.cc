// The gyroscope's maximum-likelihood calibration (estimation/gyroscope/gyroscope_ml_calibration.h)
// on simulated hand-held sessions (studies/gyroscope_monte_carlo.h): the truth recovered within
// the sigma it reports, the sigma matching the spread over repeated sessions, the effects of
// models/gyroscope_effect_list.h recovered when estimated, the fourth-order integration rule, and
// the refusal of turns about one axis naming what they leave undetermined.

#include "estimation/gyroscope/gyroscope_ml_calibration.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "models/gyroscope.h"
#include "residuals/gyroscope_residuals.h"
#include "studies/gyroscope_monte_carlo.h"

namespace accelcal {
namespace {

std::vector<double> Truths(const GyroscopeSessionDesign& design, const std::vector<int>& effects) {
  std::vector<double> truth(design.truth.begin(), design.truth.end());
  truth.insert(truth.end(), design.offset.begin(), design.offset.end());
  for (int c : effects) truth.push_back(design.effects[c]);
  return truth;
}

std::vector<double> Estimates(const GyroscopeMlResult& fit) {
  std::vector<double> estimate(fit.parameters.begin(), fit.parameters.end());
  estimate.insert(estimate.end(), fit.offset.begin(), fit.offset.end());
  for (int c : fit.effects_estimated) estimate.push_back(fit.effects[c]);
  return estimate;
}

TEST(GyroscopeMl, RecoversAnXsensLikeGyroscopeWithinItsSigma) {
  GyroscopeSessionDesign design;
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 7);
  GyroscopeSessionFit fit;
  const Status status = SimulateAndCalibrateGyroscope(design, holds, 11, {}, &fit);
  ASSERT_TRUE(status.ok()) << status.message();
  const GyroscopeMlResult& g = fit.gyroscope;
  const std::vector<double> truth = Truths(design, {});
  const std::vector<double> estimate = Estimates(g);
  ASSERT_EQ(g.stddev.size(), 12);
  for (int i = 0; i < 12; ++i) {
    EXPECT_GT(g.stddev[i], 0.0) << g.names[i];
    EXPECT_LT(std::abs(estimate[i] - truth[i]), 4.0 * g.stddev[i])
        << g.names[i] << ": " << estimate[i] << " +- " << g.stddev[i] << ", truth " << truth[i];
  }
  // A gain to better than 1e-3 of itself, an angle to a milliradian: what 29 turns of a
  // 3-count noise give (the study gives the exact figures).
  for (int k = 0; k < 3; ++k)
    EXPECT_LT(g.stddev[kGyroscopeGainX + k] / truth[kGyroscopeGainX + k], 1e-3);
  EXPECT_GT(g.gyroscope_p_value, 1e-3)
      << "chi2 " << g.chi2_gyroscope << " on " << g.gyroscope_degrees_of_freedom;
  EXPECT_EQ(g.turns.size(), holds.size() - 1);
}

// The effects of models/gyroscope_effect_list.h simulated and estimated: each coefficient within 4
// sigma of its truth, and the 12 unknowns too.
TEST(GyroscopeMl, RecoversGSensitivityAndScaleAsymmetryWhenEstimated) {
  GyroscopeSessionDesign design;
  std::vector<int> estimated;
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      design.effects[GyroscopeEffectFirstOf<GyroscopeGSensitivityEffect>() + 3 * row + col] =
          row == col ? 2e-4 : 1e-4;
      estimated.push_back(GyroscopeEffectFirstOf<GyroscopeGSensitivityEffect>() + 3 * row + col);
    }
  }
  for (int k = 0; k < 3; ++k) {
    design.effects[GyroscopeEffectFirstOf<GyroscopeScaleAsymmetryEffect>() + k] =
        2e-3 * (k == 1 ? -1.0 : 1.0);
    estimated.push_back(GyroscopeEffectFirstOf<GyroscopeScaleAsymmetryEffect>() + k);
  }
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 3);
  GyroscopeSessionFit fit;
  const Status status = SimulateAndCalibrateGyroscope(design, holds, 5, estimated, &fit);
  ASSERT_TRUE(status.ok()) << status.message();
  const GyroscopeMlResult& g = fit.gyroscope;
  const std::vector<double> truth = Truths(design, estimated);
  const std::vector<double> estimate = Estimates(g);
  ASSERT_EQ(estimate.size(), truth.size());
  ASSERT_EQ(g.stddev.size(), static_cast<int>(truth.size()));
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_LT(std::abs(estimate[i] - truth[i]), 4.0 * g.stddev[i])
        << g.names[i] << ": " << estimate[i] << " +- " << g.stddev[i] << ", truth " << truth[i];
  }
  // The g-sensitivity is seen at rest (a rate of G g n_p in every pose), to a few percent of
  // 2e-4 (rad/s)/(m/s^2).
  EXPECT_LT(g.stddev[kGyroscopeCalibrationCount], 2e-5);
}

// The reported sigma against the spread of 120 sessions of one design: every ratio within
// [0.75, 1.25] (the ratio's own sd is 6.5% at 120 trials; gyroscope_study --trials=1000 gives
// 0.977 to 1.027, docs/gyroscope.md), no bias beyond 0.35 sigma (3 sd at 120 trials).
TEST(GyroscopeMl, ReportedSigmaMatchesTheSpreadOverSessions) {
  GyroscopeMonteCarloOptions options;
  options.trials = 120;
  options.seed = 4;
  GyroscopeMonteCarloResult result;
  ASSERT_TRUE(RunGyroscopeMonteCarlo(options, &result).ok());
  ASSERT_FALSE(result.refused) << result.refusal;
  EXPECT_EQ(result.succeeded, 120) << result.first_failure;
  EXPECT_EQ(result.clipped_turns, 0) << "turns of a design within range taken for clipped";
  ASSERT_EQ(result.unknowns.size(), 12u);
  for (const GyroscopeUnknownStudy& row : result.unknowns) {
    EXPECT_GT(row.ratio, 0.75) << row.name;
    EXPECT_LT(row.ratio, 1.25) << row.name;
    EXPECT_LT(std::abs(row.bias_sigma), 0.35) << row.name;
  }
  EXPECT_GT(result.mean_chi2_per_dof, 0.9);
  EXPECT_LT(result.mean_chi2_per_dof, 1.1);
}

// The time offset (models/gyroscope_effects/time_offset.h, first order) simulated at its example
// (the gyroscope 2 ms behind) and estimated over 150 sessions of the study's design, whose turns
// start at a pose's last sample: its sigma within [0.8, 1.2] of the spread (the ratio's own sd is
// 6% at 150 trials; gyroscope_study --trials=400 --effects=time_offset gives 1.001), its bias
// within 0.45 sigma (-0.26 measured over 400: the second-order term), and the 12 unknowns' ratios
// as without it.
TEST(GyroscopeMl, TimeOffsetSigmaMatchesTheSpreadOverSessions) {
  constexpr int kTimeOffset = GyroscopeEffectFirstOf<GyroscopeTimeOffsetEffect>();
  GyroscopeMonteCarloOptions options;
  options.trials = 150;
  options.seed = 3;
  options.design.effects[kTimeOffset] = GyroscopeTimeOffsetEffect::kInfo.example[0];
  options.estimated = {kTimeOffset};
  GyroscopeMonteCarloResult result;
  ASSERT_TRUE(RunGyroscopeMonteCarlo(options, &result).ok());
  ASSERT_FALSE(result.refused) << result.refusal;
  EXPECT_EQ(result.succeeded, 150) << result.first_failure;
  ASSERT_EQ(result.unknowns.size(), 13u);
  const GyroscopeUnknownStudy& offset = result.unknowns.back();
  EXPECT_EQ(offset.name, "gyroscope_time_offset");
  EXPECT_GT(offset.ratio, 0.8);
  EXPECT_LT(offset.ratio, 1.2);
  EXPECT_LT(std::abs(offset.bias_sigma), 0.45);
  for (const GyroscopeUnknownStudy& row : result.unknowns) {
    EXPECT_GT(row.ratio, 0.75) << row.name;
    EXPECT_LT(row.ratio, 1.3) << row.name;
  }
}

// A gyroscope whose y and z outputs are stuck at their offsets (a dead channel): the turns go
// about every axis, but nothing in the data depends on the y and z gains and angles. Refused,
// naming them and the channel, not asking for turns the session already has.
TEST(GyroscopeMl, RefusesDeadChannelsNamingWhatTheyLeaveUndetermined) {
  GyroscopeSessionDesign design;
  design.gyroscope_noise = {3.0, 0.0, 0.0};
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 7);
  GyroscopeSessionFit fit;
  ASSERT_TRUE(SimulateAndCalibrateGyroscope(design, holds, 11, {}, &fit).ok());
  TriadLog log = fit.session.log;
  for (size_t i = 0; i < log.size(); ++i) {
    log.gyroscope[i][1] = design.offset[1] + (i % 2 == 0 ? 1.0 : 0.0);
    log.gyroscope[i][2] = design.offset[2] + (i % 3 == 0 ? 1.0 : 0.0);
  }
  GyroscopeMlOptions options;
  options.gravity_mps2 = design.gravity_mps2;
  options.initial = GyroscopeParametersWithGain(2.1e-4, 2.1e-4, 2.1e-4);
  options.quantisation_step = 1.0;
  GyroscopeMlResult result;
  const Status status = CalibrateGyroscopeMl(log, fit.intervals, fit.accelerometer_options,
                                             fit.accelerometer, options, &result);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("gyroscope_gain_y"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("gyroscope_gain_z"), std::string::npos) << status.message();
  EXPECT_EQ(status.message().find("gyroscope_gain_x"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("dead"), std::string::npos) << status.message();
  EXPECT_TRUE(result.turn_axes_to_add.empty());
}

// A log with too few poses for the turns to leave a degree of freedom is refused, and a log
// without gyroscope samples is refused saying so.
TEST(GyroscopeMl, RefusesALogWithoutAGyroscope) {
  GyroscopeSessionDesign design;
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 7);
  GyroscopeSessionFit fit;
  ASSERT_TRUE(SimulateAndCalibrateGyroscope(design, holds, 11, {}, &fit).ok());
  TriadLog log = fit.session.log;
  log.gyroscope.clear();
  GyroscopeMlResult result;
  const Status status = CalibrateGyroscopeMl(log, fit.intervals, fit.accelerometer_options,
                                             fit.accelerometer, GyroscopeMlOptions(), &result);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("no gyroscope samples"), std::string::npos) << status.message();
}

// The fourth-order rule against imu_tk's on a hand's turn about a fixed axis, rate
// (Theta pi / 2T) sin(pi t / T) sampled at 100 Hz: imu_tk's comes out short by
// dt^2 Theta pi^2 / (12 T^2) (docs/gyroscope.md), the Hermite rule within 1e-7 rad.
TEST(GyroscopeIntegration, HermiteRuleRemovesTheTrapezoidError) {
  const double theta = M_PI / 2.0, duration = 1.5, dt = 0.01;
  const int steps = static_cast<int>(std::lround(duration / dt));
  std::vector<double> step_s(steps, dt);
  auto rate_at = [&](int j, double* rate) {
    rate[0] = theta * M_PI / (2.0 * duration) * std::sin(M_PI * j * dt / duration);
    rate[1] = rate[2] = 0.0;
  };
  double imu_tk[9], hermite[9];
  IntegrateAngularRate(steps + 1, rate_at, step_s, imu_tk);
  IntegrateAngularRateHermite(steps + 1, rate_at, step_s, hermite);
  const double imu_tk_angle = std::atan2(imu_tk[7], imu_tk[8]);
  const double hermite_angle = std::atan2(hermite[7], hermite[8]);
  const double trapezoid_error = dt * dt * theta * M_PI * M_PI / (12.0 * duration * duration);
  EXPECT_NEAR(theta - imu_tk_angle, trapezoid_error, 0.02 * trapezoid_error);
  EXPECT_LT(std::abs(theta - hermite_angle), 1e-7);
  EXPECT_GT(trapezoid_error, 1e-5);
}

// The turn residual's derivatives by transport (the default) against those carried through the
// Runge-Kutta stages by ceres::Jet, on every turn of a simulated session, at the truth: the
// largest difference of any derivative is below 1e-3 of that column's largest (the transport's
// O((w dt)^2) at 100 Hz and rates of a few rad/s), and the residuals are the same.
TEST(GyroscopeTurnResidual, TransportedDerivativesMatchTheRungeKuttaOnes) {
  GyroscopeSessionDesign design;
  design.effects[GyroscopeEffectFirstOf<GyroscopeGSensitivityEffect>() + 1] = 1e-4;
  design.effects[GyroscopeEffectFirstOf<GyroscopeScaleAsymmetryEffect>()] = 2e-3;
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 7);
  GyroscopeSessionFit fit;
  ASSERT_TRUE(SimulateAndCalibrateGyroscope(design, holds, 11, {}, &fit).ok());
  const TriadLog& log = fit.session.log;
  std::vector<int> estimated;
  for (int c = 0; c < kGyroscopeEffectCoefficientCount; ++c) estimated.push_back(c);
  double worst = 0.0;
  for (size_t p = 0; p + 1 < fit.intervals.size(); ++p) {
    GyroscopeTurnSamples samples;
    for (int i = fit.intervals[p].end; i <= fit.intervals[p + 1].start; ++i) {
      samples.raw.push_back(log.gyroscope[i]);
      samples.specific_force.push_back({0.0, 0.0, 9.81});
      if (i < fit.intervals[p + 1].start)
        samples.step_s.push_back(log.timestamp_s[i + 1] - log.timestamp_s[i]);
    }
    const std::array<std::array<double, 3>, 2> basis = {{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}}};
    GyroscopeTurnResidual transported(samples, basis, {1.0, 0.0, 0.0, 1.0}, estimated);
    GyroscopeTurnResidual exact(samples, basis, {1.0, 0.0, 0.0, 1.0}, estimated);
    exact.set_exact_derivatives(true);
    const std::array<double, 3>& before = fit.accelerometer.directions[p];
    const std::array<double, 3>& after = fit.accelerometer.directions[p + 1];
    const double* blocks[5] = {design.truth.data(), design.offset.data(), design.effects.data(),
                               before.data(), after.data()};
    std::vector<double> j0[2][5], j1[2][5];
    const int sizes[5] = {kGyroscopeParameterCount, 3, kGyroscopeEffectCoefficientCount, 3, 3};
    double* jacobians[2][5];
    for (int which = 0; which < 2; ++which) {
      for (int b = 0; b < 5; ++b) {
        (which == 0 ? j0 : j1)[0][b].assign(2 * sizes[b], 0.0);
        jacobians[which][b] = (which == 0 ? j0 : j1)[0][b].data();
      }
    }
    double r0[2], r1[2];
    ASSERT_TRUE(transported.Evaluate(blocks, r0, jacobians[0]));
    ASSERT_TRUE(exact.Evaluate(blocks, r1, jacobians[1]));
    EXPECT_NEAR(r0[0], r1[0], 1e-12);
    EXPECT_NEAR(r0[1], r1[1], 1e-12);
    for (int b = 0; b < 3; ++b) {
      for (int u = 0; u < sizes[b]; ++u) {
        const double scale = std::max(std::abs(j1[0][b][u]), std::abs(j1[0][b][sizes[b] + u]));
        if (scale == 0.0) continue;
        for (int row = 0; row < 2; ++row) {
          worst = std::max(
              worst, std::abs(j0[0][b][row * sizes[b] + u] - j1[0][b][row * sizes[b] + u]) / scale);
        }
      }
    }
  }
  EXPECT_LT(worst, 1e-3) << worst;
  EXPECT_GT(worst, 0.0);  // two computations, not one
}

// The transported derivatives as TransportedJacobian writes them out (sums of per-sample weights)
// against the same sum taken with a ceres::Jet of the calibrated rate at every sample, for every
// effect coefficient non-zero and a specific force that changes through the turn: the same to
// rounding (1e-10 of each column's largest), whichever groups of effects are differentiated.
TEST(GyroscopeTurnResidual, TransportedDerivativesAreTheJetSumsWrittenOut) {
  GyroscopeSessionDesign design;
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 7);
  GyroscopeSessionFit fit;
  ASSERT_TRUE(SimulateAndCalibrateGyroscope(design, holds, 13, {}, &fit).ok());
  const TriadLog& log = fit.session.log;
  GyroscopeEffectCoefficients effects{};
  for (int c = 0; c < kGyroscopeEffectCoefficientCount; ++c)
    effects[c] = (c % 2 == 0 ? 1.0 : -1.0) *
                 (c < GyroscopeEffectFirstOf<GyroscopeScaleAsymmetryEffect>() ? 2e-4 : 3e-3);
  constexpr int kTimeOffset = GyroscopeEffectFirstOf<GyroscopeTimeOffsetEffect>();
  const std::vector<std::vector<int>> estimated_sets = {
      {},
      {12, 13, 14},
      {0, 1, 2, 3, 4, 5, 6, 7, 8},
      {9, 10, 11, 12, 13, 14},
      {kTimeOffset},
      {0, 4, 8, kTimeOffset},
      [] {
        std::vector<int> all;
        for (int c = 0; c < kGyroscopeEffectCoefficientCount; ++c) all.push_back(c);
        return all;
      }()};
  constexpr int kUnknowns = GyroscopeTurnResidual::kUnknowns;
  using Jet = ceres::Jet<double, kUnknowns>;
  int compared = 0;
  for (const std::vector<int>& estimated : estimated_sets) {
    double worst = 0.0;
    for (size_t p = 0; p + 1 < fit.intervals.size(); ++p) {
      GyroscopeTurnSamples samples;
      for (int i = fit.intervals[p].end; i <= fit.intervals[p + 1].start; ++i) {
        samples.raw.push_back(log.gyroscope[i]);
        const double s = 0.01 * (i - fit.intervals[p].end);
        samples.specific_force.push_back({1.0 + s, -2.0 * s, 9.81 - s});
        samples.output_rate.push_back({(log.gyroscope[i + 1][0] - log.gyroscope[i - 1][0]) * 50.0,
                                       (log.gyroscope[i + 1][1] - log.gyroscope[i - 1][1]) * 50.0,
                                       (log.gyroscope[i + 1][2] - log.gyroscope[i - 1][2]) * 50.0});
        if (i < fit.intervals[p + 1].start)
          samples.step_s.push_back(log.timestamp_s[i + 1] - log.timestamp_s[i]);
      }
      const std::array<std::array<double, 3>, 2> basis = {{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}}};
      GyroscopeTurnResidual residual(samples, basis, {1.0, 0.0, 0.0, 1.0}, estimated);
      const std::array<double, 3>& before = fit.accelerometer.directions[p];
      const std::array<double, 3>& after = fit.accelerometer.directions[p + 1];
      const double* blocks[5] = {design.truth.data(), design.offset.data(), effects.data(),
                                 before.data(), after.data()};
      const int sizes[3] = {kGyroscopeParameterCount, 3, kGyroscopeEffectCoefficientCount};
      std::vector<double> storage[3];
      double* jacobians[5] = {nullptr, nullptr, nullptr, nullptr, nullptr};
      // No effect estimated: Ceres holds the effects' block constant and asks for no derivative.
      const int blocks_differentiated = estimated.empty() ? 2 : 3;
      for (int b = 0; b < blocks_differentiated; ++b) {
        storage[b].assign(2 * sizes[b], 0.0);
        jacobians[b] = storage[b].data();
      }
      double r[2];
      ASSERT_TRUE(residual.Evaluate(blocks, r, jacobians));

      // The reference: D = sum_j c_j R_N^T R_j dw_j/du with every unknown a Jet.
      const int count = static_cast<int>(samples.raw.size());
      std::vector<std::array<double, 4>> path;
      double rotation[9];
      IntegrateAngularRateHermite(
          count,
          [&](int j, double* rate) {
            GyroscopeSampleContext<double> context;
            context.specific_force = samples.specific_force[j].data();
            context.output_rate = samples.output_rate[j].data();
            GyroscopeCorrectedRate(blocks[0], blocks[1], blocks[2], samples.raw[j].data(), context,
                                   rate);
          },
          samples.step_s, rotation, &path);
      Jet parameters[kGyroscopeParameterCount], offset[3],
          jet_effects[kGyroscopeEffectCoefficientCount];
      for (int i = 0; i < kGyroscopeParameterCount; ++i) parameters[i] = Jet(blocks[0][i], i);
      for (int i = 0; i < 3; ++i) offset[i] = Jet(blocks[1][i], 9 + i);
      for (int i = 0; i < kGyroscopeEffectCoefficientCount; ++i)
        jet_effects[i] = Jet(effects[i], 12 + i);
      double end[9];
      QuaternionToRotationMatrix(path.back().data(), end);
      std::vector<std::array<double, 3>> d(kUnknowns, {0.0, 0.0, 0.0});
      for (int j = 0; j < count; ++j) {
        const double weight = 0.5 * ((j > 0 ? samples.step_s[j - 1] : 0.0) +
                                     (j + 1 < count ? samples.step_s[j] : 0.0));
        double here[9];
        QuaternionToRotationMatrix(path[j].data(), here);
        Jet rate[3], force[3], output_rate[3];
        for (int k = 0; k < 3; ++k) {
          force[k] = Jet(samples.specific_force[j][k]);
          output_rate[k] = Jet(samples.output_rate[j][k]);
        }
        GyroscopeSampleContext<Jet> context;
        context.specific_force = force;
        context.output_rate = output_rate;
        GyroscopeCorrectedRate(parameters, offset, jet_effects, samples.raw[j].data(), context,
                               rate);
        for (int u = 0; u < kUnknowns; ++u)
          for (int row = 0; row < 3; ++row)
            for (int a = 0; a < 3; ++a)
              for (int i = 0; i < 3; ++i)
                d[u][row] += weight * end[3 * i + row] * here[3 * i + a] * rate[a].v[u];
      }
      const double v[3] = {
          rotation[0] * before[0] + rotation[3] * before[1] + rotation[6] * before[2],
          rotation[1] * before[0] + rotation[4] * before[1] + rotation[7] * before[2],
          rotation[2] * before[0] + rotation[5] * before[1] + rotation[8] * before[2]};
      int first = 0;
      for (int b = 0; b < blocks_differentiated; ++b) {
        for (int i = 0; i < sizes[b]; ++i) {
          const int u = first + i;
          const bool differentiated =
              u < 12 || std::find(estimated.begin(), estimated.end(), u - 12) != estimated.end();
          const double expected[2] = {differentiated ? v[1] * d[u][2] - v[2] * d[u][1] : 0.0,
                                      differentiated ? v[2] * d[u][0] - v[0] * d[u][2] : 0.0};
          const double scale = std::max(std::abs(expected[0]), std::abs(expected[1]));
          for (int row = 0; row < 2; ++row) {
            const double got = storage[b][row * sizes[b] + i];
            if (scale == 0.0) {
              EXPECT_EQ(got, 0.0) << "unknown " << u;
            } else {
              worst = std::max(worst, std::abs(got - expected[row]) / scale);
              ++compared;
            }
          }
        }
        first += sizes[b];
      }
    }
    EXPECT_LT(worst, 1e-10) << "estimated " << estimated.size();
  }
  EXPECT_GT(compared, 1000);
}

// Which turns determine which unknown: column j of T K multiplies axis j's reading, so turns about
// j; the offsets and the g-sensitivity come from the poses at rest.
TEST(GyroscopeMl, NamesTheAxisTurnsMustBeAboutForEachUnknown) {
  const std::vector<int> effects = {GyroscopeEffectFirstOf<GyroscopeGSensitivityEffect>() + 4,
                                    GyroscopeEffectFirstOf<GyroscopeScaleAsymmetryEffect>() + 1,
                                    GyroscopeEffectFirstOf<GyroscopeScaleNonlinearityEffect>() + 2};
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeMisalignmentYz, effects), "y");
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeMisalignmentZy, effects), "z");
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeMisalignmentZx, effects), "z");
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeMisalignmentXz, effects), "x");
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeMisalignmentXy, effects), "x");
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeMisalignmentYx, effects), "y");
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeGainY, effects), "y");
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeOffsetX, effects), "");
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeCalibrationCount, effects), "");       // G(1,1)
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeCalibrationCount + 1, effects), "y");  // asymmetry
  EXPECT_STREQ(GyroscopeTurnAxisOf(kGyroscopeCalibrationCount + 2, effects), "z");  // k2_z
}

// A gyroscope whose range is too small for the faster turns: its x output clipped at 2.3 rad/s
// above the offset. The turns in which it sits at that rail are left out and listed, and the
// others still give the truth within 4 sigma; without the rule the clipped turns' short
// rotations bias the gains.
TEST(GyroscopeMl, LeavesOutTurnsWhereAnOutputSitsAtTheEndOfItsRange) {
  GyroscopeSessionDesign design;
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 7);
  GyroscopeSessionFit fit;
  ASSERT_TRUE(SimulateAndCalibrateGyroscope(design, holds, 11, {}, &fit).ok());
  TriadLog log = fit.session.log;
  const double rail = std::round(design.offset[0] + 2.3 / design.truth[kGyroscopeGainX]);
  int clipped_samples = 0;
  for (std::array<double, 3>& u : log.gyroscope) {
    if (u[0] > rail) {
      u[0] = rail;
      ++clipped_samples;
    }
  }
  ASSERT_GT(clipped_samples, 20) << "the test needs turns faster than the rail";
  GyroscopeMlResult result;
  ASSERT_TRUE(CalibrateGyroscopeMl(log, fit.intervals, fit.accelerometer_options, fit.accelerometer,
                                   fit.gyroscope_options, &result)
                  .ok());
  ASSERT_FALSE(result.clipped_turns.empty());
  for (const GyroscopeClippedTurn& turn : result.clipped_turns) {
    EXPECT_EQ(turn.axis, 0);
    EXPECT_DOUBLE_EQ(turn.rail, rail);
  }
  EXPECT_EQ(result.turns.size() + result.clipped_turns.size(), holds.size() - 1);
  const std::vector<double> truth = Truths(design, {});
  const std::vector<double> estimate = Estimates(result);
  for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
    EXPECT_LT(std::abs(estimate[i] - truth[i]), 4.0 * result.stddev[i])
        << result.names[i] << ": " << estimate[i] << " +- " << result.stddev[i];
  }
}
}  // namespace
}  // namespace accelcal
