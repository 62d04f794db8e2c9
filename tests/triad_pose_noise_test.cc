// The quantisation term of the pose means (estimation/triad/triad_pose_noise.h): B(sigma, q)
// against the rounded means of simulated samples, and the calibration of quantised sessions
// whose reported sigmas must match the Monte Carlo spread about the truth.

#include "estimation/triad/triad_pose_noise.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "estimation/triad/triad_session_calibration.h"
#include "models/triad.h"
#include "simulation/random.h"
#include "simulation/triad_log_simulator.h"
#include "simulation/triad_simulator.h"

namespace accelcal {
namespace {

TEST(TriadPoseNoise, QuantisationBiasVarianceIsTheRoundedMeansErrorBySimulation) {
  EXPECT_DOUBLE_EQ(QuantisationBiasVariance(0.0, 2.0), 4.0 / 12.0);
  EXPECT_LT(QuantisationBiasVariance(9.0, 1.0), 1e-150);  // sigma = 3 q: dithered away
  RandomSource random(3101);
  for (const double sigma : {0.05, 0.1, 0.2, 0.3}) {
    // Means of 400 rounded samples about mu uniform on the grid: their error's mean square
    // is B + (variance of a rounded sample) / 400; the second part from the same draws.
    constexpr int kMeans = 4000;
    constexpr int kSamples = 400;
    double squared_error = 0.0;
    double within = 0.0;
    for (int m = 0; m < kMeans; ++m) {
      const double mu = random.Uniform();
      double sum = 0.0;
      double sum_squares = 0.0;
      for (int i = 0; i < kSamples; ++i) {
        const double y = std::round(mu + sigma * random.StandardNormal());
        sum += y;
        sum_squares += y * y;
      }
      const double mean = sum / kSamples;
      squared_error += (mean - mu) * (mean - mu);
      within += (sum_squares - sum * mean) / (kSamples - 1);
    }
    within /= kMeans;
    const double bias = squared_error / kMeans - within / kSamples;
    const double model = QuantisationBiasVariance(sigma * sigma, 1.0);
    std::printf(
        "[ quantised ] sigma = %.2f q: B = %.4g q^2 (model %.4g), s^2 = %.4g (sigma from "
        "it %.4f)\n",
        sigma, bias, model, within, std::sqrt(UnroundedNoiseVariance(within, 1.0)));
    EXPECT_NEAR(bias, model, 0.06 * model + 2e-5);
    EXPECT_NEAR(std::sqrt(UnroundedNoiseVariance(within, 1.0)), sigma, 0.05 * sigma);
  }
}

// A 12-bit sensor at 1024 counts per g, noise sigma below its step: 30 poses of 6 s. Before the
// quantisation term the fits were off by tens of sigma (chi2/dof 371 at sigma = 0.1 count).
TEST(TriadPoseNoise, QuantisedSessionsSigmasMatchTheMonteCarloSpread) {
  TriadLogSimulationOptions simulation;
  simulation.truth = TriadParametersWithOffset(7.0, -12.0, 20.0);
  simulation.truth[kTriadMisalignmentYz] = 0.004;
  simulation.truth[kTriadMisalignmentZy] = -0.006;
  simulation.truth[kTriadMisalignmentZx] = 0.008;
  simulation.truth[kTriadGainX] = 9.81 / 1024 * 1.012;
  simulation.truth[kTriadGainY] = 9.81 / 1024 * 0.991;
  simulation.truth[kTriadGainZ] = 9.81 / 1024 * 1.005;
  simulation.gravity_mps2 = 9.81;
  for (const double sigma : {0.1, 0.3}) {
    simulation.noise_stddev = {sigma, sigma, sigma};
    RandomSource random(static_cast<uint64_t>(3200 + 10 * sigma));
    constexpr int kSessions = 60;
    std::array<double, kTriadParameterCount> z_squares{};
    double chi2_per_dof = 0.0;
    int explained = 0;
    for (int s = 0; s < kSessions; ++s) {
      const std::vector<TriadHold> holds = RandomSeparatedHolds(30, 6.0, 30.0, &random);
      const TriadLog log = SimulateTriadSession(simulation, holds, &random).log;
      TriadSessionOptions options;
      options.gravity_mps2 = 9.81;
      TriadSessionCalibration calibration;
      const Status status = CalibrateTriadSession(log, options, &calibration);
      ASSERT_TRUE(status.ok()) << status.message();
      for (int p = 0; p < kTriadParameterCount; ++p) {
        const double z =
            (calibration.ml.parameters[p] - simulation.truth[p]) / calibration.ml.stddev[p];
        z_squares[p] += z * z / kSessions;
      }
      chi2_per_dof += calibration.ml.chi2_per_dof / kSessions;
      explained += calibration.discovery.verdict_code == Verdict::kExplained;
      if (calibration.discovery.verdict_code != Verdict::kExplained)
        std::printf("[ quantised ] not explained: %s\n", calibration.discovery.verdict.c_str());
    }
    // The spread about the truth over the reported sigma, per parameter: 1 when honest (its
    // estimate from 60 sessions has a standard error of about 0.09).
    double worst = 0.0;
    for (int p = 0; p < kTriadParameterCount; ++p) {
      const double ratio = std::sqrt(z_squares[p]);
      std::printf("[ quantised ] sigma = %.1f count: %-16s spread / sigma = %.2f\n", sigma,
                  TriadParameterInfos()[p].name, ratio);
      worst = std::max(worst, std::abs(std::log(ratio)));
    }
    std::printf("[ quantised ] sigma = %.1f count: mean chi2/dof %.2f, explained %d of %d\n", sigma,
                chi2_per_dof, explained, kSessions);
    EXPECT_LT(worst, std::log(1.35)) << "sigma = " << sigma;
    EXPECT_NEAR(chi2_per_dof, 1.0, 0.25) << "sigma = " << sigma;
    EXPECT_GE(explained, kSessions * 9 / 10) << "sigma = " << sigma;
  }
}

}  // namespace
}  // namespace accelcal
