// The Allan variance, its intervals and its noise fit against simulated noise of known terms
// (simulation/noise_process.h), Monte Carlo.

#include "estimation/statistics/allan_variance.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "common/format.h"
#include "simulation/noise_process.h"
#include "simulation/random.h"
#include "studies/allan_study.h"

namespace accelcal {
namespace {

// An Xsens-like axis in m/s^2 at 100 Hz: N = 1e-3 (m/s^2)/sqrt(Hz) and K = 2e-4 (m/s^2) sqrt(Hz),
// so that the random walk overtakes white noise at tau = sqrt(3) N / K = 8.7 s, within a
// 200 s series.
NoiseProcessParameters WhiteAndWalk() {
  NoiseProcessParameters parameters;
  parameters.sample_period_s = 0.01;
  parameters.white_density = 1e-3;
  parameters.random_walk = 2e-4;
  return parameters;
}

constexpr long long kSamples = 20000;
constexpr int kSeries = 200;

// The fraction of `hits` out of `count`, with the binomial sigma at probability p.
double BinomialSigma(double p, int count) { return std::sqrt(p * (1.0 - p) / count); }

TEST(AllanVariance, IsExactForAConstantPlusALine) {
  // A ramp y = a + b i has sigma^2(m) = (b m)^2 / 2: adjacent means differ by b m.
  std::vector<double> ramp(1000);
  for (size_t i = 0; i < ramp.size(); ++i) ramp[i] = 32768.0 + 0.5 * static_cast<double>(i);
  AllanCurve curve;
  ASSERT_TRUE(ComputeAllanVariance({ramp}, 0.01, AllanOptions(), &curve).ok());
  ASSERT_EQ(curve.points.size(), 8u);  // m = 1 .. 128, 4 m <= 1000
  for (const AllanPoint& point : curve.points) {
    const double m = static_cast<double>(point.cluster_samples);
    EXPECT_NEAR(point.avar, 0.125 * m * m, 1e-9 * m * m) << "m = " << m;
    EXPECT_EQ(point.difference_count, 1000 - 2 * point.cluster_samples + 1);
    EXPECT_EQ(point.independent_clusters, 1000 / point.cluster_samples);
  }
}

// The overlapping Allan variance as the textbook states it, directly: the means of every run of m
// samples, and half the mean square difference of each with the one m samples later, over every
// start k = 0 .. n - 2m (O(n m) per tau), in long double.
double TextbookOverlappingAllanVariance(const std::vector<double>& y, long long m) {
  // Less the first sample, exactly (Sterbenz: every sample is within a factor 2 of it here), so
  // that the means lose no digits to the offset whatever the width of long double.
  const long long n = static_cast<long long>(y.size());
  std::vector<long double> means(static_cast<size_t>(n - m + 1));
  for (long long k = 0; k + m <= n; ++k) {
    long double sum = 0.0L;
    for (long long j = k; j < k + m; ++j) sum += y[j] - y[0];
    means[k] = sum / m;
  }
  long double total = 0.0L;
  for (long long k = 0; k + 2 * m <= n; ++k)
    total += (means[k + m] - means[k]) * (means[k + m] - means[k]);
  return static_cast<double>(total / (2.0L * static_cast<long double>(n - 2 * m + 1)));
}

// A segment handed to AddStreamed from `y`.
AllanVarianceAccumulator::SegmentReader ReaderOf(const std::vector<double>& y) {
  return [&y](long long first, long long count, double* values) {
    EXPECT_LE(first + count, static_cast<long long>(y.size()));
    for (long long i = 0; i < count; ++i) values[i] = y[first + i];
    return Status::Ok();
  };
}

// The fast paths (cumulative sums: Add, and AddStreamed with its ring of sums and, for lags
// beyond the ring, cursors reading the segment again) against the textbook computation on a few
// thousand samples of white noise and random walk on an ADC offset: every octave tau to 1e-12,
// and AddStreamed the same as Add to the last bit whatever the ring's size.
TEST(AllanVariance, FastPathsEqualTheTextbookOverlappingEstimator) {
  NoiseProcessParameters parameters = WhiteAndWalk();
  RandomSource random(49, 1);
  for (const long long n : {4000LL, 5003LL}) {
    std::vector<double> y = SimulateNoiseProcess(parameters, n, &random);
    for (double& v : y) v += 9.81;  // an offset, as raw data have
    AllanCurve whole;
    ASSERT_TRUE(ComputeAllanVariance({y}, parameters.sample_period_s, AllanOptions(), &whole).ok());
    ASSERT_EQ(whole.points.size(), n == 4000 ? 10u : 11u);  // m = 1 .. 2^9 (2^10), 4 m <= n
    for (const AllanPoint& point : whole.points) {
      const long long m = point.cluster_samples;
      const double textbook = TextbookOverlappingAllanVariance(y, m);
      EXPECT_NEAR(point.avar, textbook, 1e-12 * textbook) << "n " << n << ", m " << m;
      EXPECT_EQ(point.difference_count, n - 2 * m + 1);
      EXPECT_DOUBLE_EQ(point.tau_s, static_cast<double>(m) * parameters.sample_period_s);
    }
    // Rings from 2 sums (every lag from a cursor) to more than the segment (none).
    for (const long long held : {2LL, 64LL, 1024LL, 1LL << 19}) {
      AllanVarianceAccumulator accumulator;
      accumulator.SetHeldSums(held);
      ASSERT_TRUE(accumulator.Start(parameters.sample_period_s, AllanOptions(), {n}).ok());
      ASSERT_TRUE(accumulator.AddStreamed(n, ReaderOf(y)).ok());
      AllanCurve streamed;
      ASSERT_TRUE(accumulator.Finish(&streamed).ok());
      ASSERT_EQ(streamed.points.size(), whole.points.size());
      for (size_t i = 0; i < whole.points.size(); ++i) {
        EXPECT_EQ(streamed.points[i].avar, whole.points[i].avar) << "held " << held << ", i " << i;
        EXPECT_EQ(streamed.points[i].difference_count, whole.points[i].difference_count);
        EXPECT_EQ(streamed.points[i].independent_clusters, whole.points[i].independent_clusters);
      }
    }
  }
}

// Segments pooled, streamed with a small ring: the same curve as ComputeAllanVariance's to the
// last bit, and a non-finite sample refused with the same message.
TEST(AllanVariance, StreamedSegmentsPoolAsTheWholeOnes) {
  RandomSource random(50);
  NoiseProcessParameters parameters = WhiteAndWalk();
  const std::vector<std::vector<double>> segments = {
      SimulateNoiseProcess(parameters, 3000, &random),
      SimulateNoiseProcess(parameters, 70, &random),
      SimulateNoiseProcess(parameters, 1200, &random)};
  AllanCurve whole;
  ASSERT_TRUE(ComputeAllanVariance(segments, 0.01, AllanOptions(), &whole).ok());
  AllanVarianceAccumulator accumulator;
  accumulator.SetHeldSums(128);
  ASSERT_TRUE(accumulator.Start(0.01, AllanOptions(), {3000, 70, 1200}).ok());
  for (const std::vector<double>& segment : segments) {
    ASSERT_TRUE(
        accumulator.AddStreamed(static_cast<long long>(segment.size()), ReaderOf(segment)).ok());
  }
  AllanCurve streamed;
  ASSERT_TRUE(accumulator.Finish(&streamed).ok());
  ASSERT_EQ(streamed.points.size(), whole.points.size());
  for (size_t i = 0; i < whole.points.size(); ++i) {
    EXPECT_EQ(streamed.points[i].avar, whole.points[i].avar) << i;
    EXPECT_EQ(streamed.points[i].edf, whole.points[i].edf) << i;
  }
  std::vector<double> broken = segments[2];
  broken[17] = NAN;
  AllanVarianceAccumulator refusing;
  ASSERT_TRUE(refusing.Start(0.01, AllanOptions(), {1200}).ok());
  const Status status = refusing.AddStreamed(1200, ReaderOf(broken));
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.message(), "segment 1, sample 18 is not finite");
}

TEST(AllanVariance, RefusesTooShortAndNonFiniteSegments) {
  AllanCurve curve;
  EXPECT_FALSE(ComputeAllanVariance({{1.0, 2.0, 3.0}}, 0.01, AllanOptions(), &curve).ok());
  EXPECT_FALSE(
      ComputeAllanVariance({{1.0, 2.0, NAN, 3.0, 4.0}}, 0.01, AllanOptions(), &curve).ok());
  EXPECT_FALSE(ComputeAllanVariance({{1.0, 2.0, 3.0, 4.0}}, 0.0, AllanOptions(), &curve).ok());
}

TEST(AllanVariance, PoolsSegmentsWithoutDifferencesAcrossThem) {
  // Two white segments with very different means pool to the white variance: no difference
  // spans the jump between them.
  RandomSource random(7);
  NoiseProcessParameters white;
  white.white_density = 1e-3;
  std::vector<double> first = SimulateNoiseProcess(white, 5000, &random);
  std::vector<double> second = SimulateNoiseProcess(white, 5000, &random);
  for (double& v : second) v += 100.0;
  AllanCurve curve;
  ASSERT_TRUE(ComputeAllanVariance({first, second}, 0.01, AllanOptions(), &curve).ok());
  for (const AllanPoint& point : curve.points) {
    const double exact = NoiseProcessAllanVariance(white, point.cluster_samples);
    EXPECT_NEAR(point.avar / exact, 1.0, 4.0 * std::sqrt(2.0 / point.edf)) << point.tau_s;
  }
}

// Each tau's 95% chi-square interval (with the fitted model's dominant noise setting the
// degrees of freedom) covers the exact Allan variance of white + random walk + Gauss-Markov
// noise about 95% of the time. Measured (200 series, 11 taus): 0.93 to 0.97 per tau.
TEST(AllanVariance, IntervalsCoverTheExactAllanVariance) {
  NoiseProcessParameters parameters = WhiteAndWalk();
  parameters.markov.push_back({5e-4, 2.0});
  std::vector<int> covered;
  std::vector<int> counted;
  for (int series = 0; series < kSeries; ++series) {
    RandomSource random(2021, series);
    AllanCurve curve;
    AllanNoiseFit fit;
    ASSERT_TRUE(ComputeAllanVariance({SimulateNoiseProcess(parameters, kSamples, &random)},
                                     parameters.sample_period_s, AllanOptions(), &curve)
                    .ok());
    ASSERT_TRUE(FitAllanNoise(AllanOptions(), &curve, &fit).ok());
    covered.resize(curve.points.size());
    counted.resize(curve.points.size());
    for (size_t i = 0; i < curve.points.size(); ++i) {
      const AllanPoint& point = curve.points[i];
      const double exact = NoiseProcessAllanVariance(parameters, point.cluster_samples);
      covered[i] += point.avar_low <= exact && exact <= point.avar_high;
      ++counted[i];
    }
  }
  for (size_t i = 0; i < covered.size(); ++i) {
    const double rate = static_cast<double>(covered[i]) / counted[i];
    std::printf("tau index %zu: coverage %.3f\n", i, rate);
    EXPECT_NEAR(rate, 0.95, 4.0 * BinomialSigma(0.95, counted[i])) << "tau index " << i;
  }
}

// Coverage of the fit's stated intervals (studies/allan_study.h) over kSeries simulated series
// of `truth`: a term is covered when its interval (resolved: low .. high; not resolved: 0 ..
// upper bound) holds the truth. One bootstrap table of kBootstrapSeries serves every series, as
// one table serves the three axes of a log: the coverage measured is the one given that table,
// which differs from the average over tables by well under the binomial sigma (the 2.5% tail of
// 1000 series is placed to +-0.5%).
struct Coverage {
  std::array<int, 3> covered{};         // N, B, K
  std::array<int, 3> resolved{};        // intervals excluding 0
  std::array<int, 3> bound_covered{};   // of the not resolved: truth <= upper bound
  std::array<int, 3> normal_covered{};  // value +- z sigma, for comparison (resolved only)
  int chi2_rare = 0;  // series whose chi2 fewer than 5% of the bootstrap's series reach
  int series = 0;
};

constexpr int kBootstrapSeries = 1000;

// `segments` (lengths) pooled, the bootstrap simulating at most `max_simulated_samples` beyond
// the longest segment (studies/allan_study.h, "Long data").
Coverage MeasureCoverage(const AllanNoiseTerms& truth, uint64_t seed,
                         const std::vector<long long>& segments = {kSamples},
                         long long max_simulated_samples = 1 << 16,
                         long long max_segment_samples = 1 << 16,
                         long long piece_samples = 1 << 12) {
  std::vector<std::vector<double>> zeros;
  for (long long n : segments) zeros.emplace_back(n, 0.0);
  // The curve's shape (segments and taus), which the truth's bias-instability bank and the
  // bootstrap table are made for; every series has the same.
  AllanCurve shape;
  EXPECT_TRUE(ComputeAllanVariance(zeros, 0.01, AllanOptions(), &shape).ok());
  const NoiseProcessParameters process = AllanModelProcess(truth, shape);
  AllanBootstrapTable table;
  AllanBootstrapOptions bootstrap;
  bootstrap.series = kBootstrapSeries;
  bootstrap.seed = seed + 1;
  bootstrap.max_simulated_samples = max_simulated_samples;
  bootstrap.max_segment_samples = max_segment_samples;
  bootstrap.piece_samples = piece_samples;
  EXPECT_TRUE(MakeAllanBootstrapTable(AllanOptions(), shape, bootstrap, &table).ok());
  const std::array<double, 3> true_values = {truth.white_density, truth.bias_instability,
                                             truth.random_walk};
  const double z = 1.959964;
  Coverage coverage;
  for (int series = 0; series < kSeries; ++series) {
    RandomSource random(seed, series);
    AllanCurve curve;
    AllanNoiseFit fit;
    std::vector<std::vector<double>> data;
    for (long long n : segments) data.push_back(SimulateNoiseProcess(process, n, &random));
    EXPECT_TRUE(ComputeAllanVariance(data, process.sample_period_s, AllanOptions(), &curve).ok());
    const Status status = FitAllanNoiseWithBootstrap(AllanOptions(), table, &curve, &fit);
    EXPECT_TRUE(status.ok()) << status.message();
    const AllanTerm* terms[3] = {&fit.white, &fit.bias_instability, &fit.random_walk};
    for (int j = 0; j < 3; ++j) {
      const AllanTerm& term = *terms[j];
      const double t = true_values[j];
      const bool inside = (term.resolved ? term.low : 0.0) <= t && t <= term.high;
      coverage.covered[j] += inside;
      coverage.resolved[j] += term.resolved;
      if (!term.resolved) coverage.bound_covered[j] += t <= term.high;
      if (term.resolved) coverage.normal_covered[j] += std::fabs(term.value - t) <= z * term.stddev;
    }
    coverage.chi2_rare += fit.chi2_bootstrap_fraction < 0.05;
    ++coverage.series;
  }
  std::printf("chi2 reached by < 5%% of the bootstrap's series in %.3f of the series\n",
              1.0 * coverage.chi2_rare / coverage.series);
  const char* names[3] = {"N", "B", "K"};
  for (int j = 0; j < 3; ++j) {
    const int unresolved = coverage.series - coverage.resolved[j];
    std::printf("%s = %.3g: 95%% interval covers %.3f of %d series; resolved in %d%s", names[j],
                true_values[j], 1.0 * coverage.covered[j] / coverage.series, coverage.series,
                coverage.resolved[j],
                unresolved > 0
                    ? StringPrintf(", upper bound of the %d not resolved covers %.3f", unresolved,
                                   1.0 * coverage.bound_covered[j] / unresolved)
                          .c_str()
                    : "");
    if (coverage.resolved[j] > 0) {
      std::printf("; value +- 1.96 sigma of the resolved covers %.3f",
                  1.0 * coverage.normal_covered[j] / coverage.resolved[j]);
    }
    std::printf("\n");
  }
  return coverage;
}

// Each term's coverage within 3 binomial sigmas of the stated 95%.
void ExpectStatedCoverage(const Coverage& coverage) {
  const double sigma = BinomialSigma(0.95, coverage.series);
  for (int j = 0; j < 3; ++j)
    EXPECT_NEAR(1.0 * coverage.covered[j] / coverage.series, 0.95, 3.0 * sigma) << "term " << j;
}

// The Done-when of issue 21: on white + random-walk noise of known N and K (B truly 0), the
// fit's 95% intervals of N, K and B cover the truth at their stated rate. The least squares
// intervals do not (N 85%, K 83%), nor did the bootstrap's sigma in a normal interval (K 86.5%:
// K^2 is skewed, see studies/allan_study.h). Measured in docs/noise.md.
TEST(AllanMonteCarlo, RecoversWhiteAndRandomWalkWithinTheStatedConfidence) {
  AllanNoiseTerms truth;
  truth.white_density = 1e-3;
  truth.random_walk = 2e-4;
  const Coverage coverage = MeasureCoverage(truth, 1952);
  ExpectStatedCoverage(coverage);
  EXPECT_EQ(coverage.resolved[0], coverage.series);  // N is always resolved
  // The model holds, so its chi2 is rare (below 5% of the bootstrap's) about 5% of the time.
  EXPECT_NEAR(1.0 * coverage.chi2_rare / coverage.series, 0.05,
              3.0 * BinomialSigma(0.05, coverage.series));
}

// With bias instability (B = 4e-4, its floor 0.664 B = 2.7e-4 against N / sqrt(tau) = 3.2e-4
// at 10 s) and a weak random walk (K = 3e-5, overtaking white noise only past 58 s, so often
// not resolved): the intervals of N and B, and of K with its upper bound when not resolved,
// cover the truth.
TEST(AllanMonteCarlo, RecoversBiasInstabilityAndBoundsAWeakRandomWalk) {
  AllanNoiseTerms truth;
  truth.white_density = 1e-3;
  truth.bias_instability = 4e-4;
  truth.random_walk = 3e-5;
  const Coverage coverage = MeasureCoverage(truth, 2718);
  ExpectStatedCoverage(coverage);
  // The weak walk is not resolved in a good share of the series, and its bound then holds.
  const int unresolved = coverage.series - coverage.resolved[2];
  ASSERT_GE(unresolved, 20);
  EXPECT_GE(1.0 * coverage.bound_covered[2] / unresolved, 0.9);
}

// Long data (studies/allan_study.h): 40 poses of 20 s pooled, the bootstrap simulating only the
// longest and every 13th of the others (a tenth of the differences, moved to the data's
// variance): the intervals cover the truth at the stated rate. Measured: N 91.5%, B 96.5%, K 95.0%
// of 200 series; the full bootstrap (no cap) on the same series: N 92.0%, B 97.5%, K 95.0%. With
// the products left at the simulated tenth's spread (not moved), every interval covered 100% and
// K was resolved in 110 of the 200 series instead of all: intervals sqrt(10) = 3.2 times too wide,
// which this test fails on.
TEST(AllanMonteCarlo, LongDataCoverageWithABoundedBootstrap) {
  AllanNoiseTerms truth;
  truth.white_density = 1e-3;
  truth.random_walk = 1e-3;
  const Coverage coverage = MeasureCoverage(truth, 3141, std::vector<long long>(40, 2000),
                                            /*max_simulated_samples=*/6000);
  ExpectStatedCoverage(coverage);
}

// The variance of a pose mean: for white noise N^2 / T against the spread of simulated T-long
// means; with random walk added, sigma^2_model(T) against half the mean square difference of
// two adjacent T-long means, the meaning docs/noise.md gives it.
// A single segment longer than the bootstrap's max_segment_samples, simulated in pieces
// (studies/allan_study.h, "Long segments"): 20,000 samples in pieces of 1024, two levels of
// resolution (1024 samples at tau0 for m <= 256, the segment's 312 blocks of 64 for the rest), so
// that both the shrunk piece and the coarse level are exercised at the cost of a short log.
// Measured (200 series): N 0.935, B 0.985, K 0.965; with B, N 0.910, B 0.915, K 0.935, where the
// whole simulation (max_segment_samples 2^16) on the same series covers 0.950, 0.975, 0.970 and
// 0.935, 0.960, 0.970 (docs/noise.md, "Long segments"). The
// stated coverage holds, with white noise and random walk, and with bias instability and a weak
// random walk.
TEST(AllanMonteCarlo, LongSegmentCoverageWithAPiecedBootstrap) {
  AllanNoiseTerms truth;
  truth.white_density = 1e-3;
  truth.random_walk = 2e-4;
  ExpectStatedCoverage(MeasureCoverage(truth, 4949, {kSamples}, 1 << 16,
                                       /*max_segment_samples=*/4096, /*piece_samples=*/1024));
  truth.bias_instability = 4e-4;
  truth.random_walk = 3e-5;
  ExpectStatedCoverage(MeasureCoverage(truth, 4950, {kSamples}, 1 << 16,
                                       /*max_segment_samples=*/4096, /*piece_samples=*/1024));
}

TEST(AllanFit, PoseMeanVarianceMatchesTheSpreadOfSimulatedMeans) {
  const double duration_s = 2.0;
  for (const bool with_walk : {false, true}) {
    NoiseProcessParameters parameters = WhiteAndWalk();
    if (!with_walk) parameters.random_walk = 0.0;
    const long long pose_samples = static_cast<long long>(duration_s / parameters.sample_period_s);
    double predicted = 0.0, observed = 0.0;
    int count = 0;
    for (int series = 0; series < kSeries; ++series) {
      RandomSource random(33, series);
      const std::vector<double> y = SimulateNoiseProcess(parameters, kSamples, &random);
      AllanCurve curve;
      AllanNoiseFit fit;
      ASSERT_TRUE(
          ComputeAllanVariance({y}, parameters.sample_period_s, AllanOptions(), &curve).ok());
      ASSERT_TRUE(FitAllanNoise(AllanOptions(), &curve, &fit).ok());
      predicted += AllanPoseMeanVariance(FittedNoiseTerms(fit), duration_s);
      // Two adjacent poses at the end of the series, about a mean of 0 when white only.
      double first = 0.0, second = 0.0;
      for (long long i = 0; i < pose_samples; ++i) {
        first += y[kSamples - 2 * pose_samples + i];
        second += y[kSamples - pose_samples + i];
      }
      first /= pose_samples;
      second /= pose_samples;
      observed += with_walk ? 0.5 * (second - first) * (second - first) : first * first;
      ++count;
    }
    predicted /= count;
    observed /= count;
    const double exact = with_walk
                             ? NoiseProcessAllanVariance(parameters, pose_samples)
                             : parameters.white_density * parameters.white_density / duration_s;
    std::printf("%s: pose mean variance over %.0f s: fitted %.4g, exact %.4g, simulated %.4g\n",
                with_walk ? "white + random walk" : "white", duration_s, predicted, exact,
                observed);
    // The simulated spread of kSeries squares has relative sigma sqrt(2 / kSeries) = 0.07.
    EXPECT_NEAR(observed / exact, 1.0, 4.0 * std::sqrt(2.0 / count));
    EXPECT_NEAR(predicted / exact, 1.0, 0.05);
  }
}

}  // namespace
}  // namespace accelcal
