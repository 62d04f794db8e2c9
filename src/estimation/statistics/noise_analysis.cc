#include "estimation/statistics/noise_analysis.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace accelcal {
namespace {

// Autocovariance of the differences d_i = e_i - e_{i-1} of AR(1) noise of variance s2.
double DifferenceAutocovariance(double s2, double rho, int lag) {
  auto gamma = [&](int h) { return s2 * std::pow(rho, std::abs(h)); };
  return 2.0 * gamma(lag) - gamma(lag - 1) - gamma(lag + 1);
}

// Covariance of (A, B) times n for Gaussian AR(1) noise (sums over every lag; the terms
// decay as rho^|h|).
Eigen::Matrix2d MomentCovariance(double s2, double rho) {
  const int lags = std::min(
      4000, 8 + static_cast<int>(40.0 / std::max(1e-3, -std::log(std::abs(rho) + 1e-300))));
  auto c = [&](int h) { return DifferenceAutocovariance(s2, rho, h); };
  double var_a = 0.0, var_b = 0.0, cov_ab = 0.0;
  for (int h = -lags; h <= lags; ++h) {
    var_a += 2.0 * c(h) * c(h);
    var_b += c(h) * c(h) + c(h - 1) * c(h + 1);
    cov_ab += 2.0 * c(h) * c(h - 1);
  }
  Eigen::Matrix2d covariance;
  covariance << var_a, cov_ab, cov_ab, var_b;
  return covariance;
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + middle, values.end());
  double median = values[middle];
  if (values.size() % 2 == 0) {
    median = 0.5 * (median + *std::max_element(values.begin(), values.begin() + middle));
  }
  return median;
}

// Anscombe and Glynn's normalising transformation of the sample kurtosis b2 of n
// independent normal values: z is about N(0, 1), large for heavy tails.
double AnscombeGlynnZ(double b2, double n) {
  const double mean = 3.0 * (n - 1.0) / (n + 1.0);
  const double variance =
      24.0 * n * (n - 2.0) * (n - 3.0) / ((n + 1.0) * (n + 1.0) * (n + 3.0) * (n + 5.0));
  const double x = (b2 - mean) / std::sqrt(variance);
  const double skew = 6.0 * (n * n - 5.0 * n + 2.0) / ((n + 7.0) * (n + 9.0)) *
                      std::sqrt(6.0 * (n + 3.0) * (n + 5.0) / (n * (n - 2.0) * (n - 3.0)));
  const double a = 6.0 + 8.0 / skew * (2.0 / skew + std::sqrt(1.0 + 4.0 / (skew * skew)));
  const double term = (1.0 - 2.0 / a) / (1.0 + x * std::sqrt(2.0 / (a - 4.0)));
  const double root = term >= 0.0 ? std::cbrt(term) : -std::cbrt(-term);
  return ((1.0 - 2.0 / (9.0 * a)) - root) / std::sqrt(2.0 / (9.0 * a));
}

}  // namespace

double TwoSidedNormalTail(double z) { return std::erfc(std::abs(z) / std::sqrt(2.0)); }

double TwoSidedNormalQuantile(double p) {
  if (!(p < 1.0)) return 0.0;
  if (!(p > 0.0)) return 40.0;
  double low = 0.0, high = 40.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double middle = 0.5 * (low + high);
    (TwoSidedNormalTail(middle) > p ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

NoiseAnalysis AnalyzeNoise(const std::vector<double>& residual, double stated_variance,
                           const std::vector<int>& excluded, bool heavy_tails,
                           const NoiseAnalysisOptions& options) {
  NoiseAnalysis result;
  const int n = static_cast<int>(residual.size());
  std::vector<char> out(n, 0);
  for (const int i : excluded) {
    if (i >= 0 && i < n) out[i] = 1;
  }
  result.samples = n - static_cast<int>(std::count(out.begin(), out.end(), 1));
  if (result.samples < 16 || !(stated_variance > 0.0)) return result;

  // Outliers: each sample against the median of its neighbours.
  std::vector<double> score(n, 0.0);
  std::vector<int> scored;
  std::vector<double> neighbours;
  for (int i = 0; i < n; ++i) {
    if (out[i]) continue;
    neighbours.clear();
    for (int j = std::max(0, i - 3); j <= std::min(n - 1, i + 3); ++j) {
      if (j != i && !out[j]) neighbours.push_back(residual[j]);
    }
    if (neighbours.size() < 2) continue;
    score[i] = residual[i] - Median(neighbours);
    scored.push_back(i);
  }
  std::vector<double> scores;
  for (const int i : scored) scores.push_back(score[i]);
  const double center = Median(scores);
  for (double& value : scores) value = std::abs(value - center);
  const double scale = 1.4826 * Median(scores);
  if (scale > 0.0) {
    const double bound =
        TwoSidedNormalQuantile(options.outlier_alpha / std::max<size_t>(1, scored.size()));
    for (const int i : scored) {
      const double z = std::abs(score[i] - center) / scale;
      result.largest_score = std::max(result.largest_score, z);
      if (z > bound) result.outlier_candidates.push_back(i);
    }
    result.outlier_p = std::min(
        1.0, static_cast<double>(scored.size()) * TwoSidedNormalTail(result.largest_score));
  }

  // Tails: pair differences, without the candidates.
  std::vector<char> left_out = out;
  for (const int i : result.outlier_candidates) left_out[i] = 1;
  std::vector<double> pairs;
  for (int i = 1; i < n; i += 2) {
    if (!left_out[i] && !left_out[i - 1]) pairs.push_back(residual[i] - residual[i - 1]);
  }
  if (pairs.size() >= 16) {
    double mean = 0.0;
    for (double value : pairs) mean += value;
    mean /= pairs.size();
    double m2 = 0.0, m4 = 0.0;
    for (double value : pairs) {
      const double d2 = (value - mean) * (value - mean);
      m2 += d2;
      m4 += d2 * d2;
    }
    m2 /= pairs.size();
    m4 /= pairs.size();
    if (m2 > 0.0) {
      const double b2 = m4 / (m2 * m2);
      result.excess_kurtosis = b2 - 3.0;
      result.kurtosis_z = AnscombeGlynnZ(b2, static_cast<double>(pairs.size()));
      result.kurtosis_p = 0.5 * std::erfc(result.kurtosis_z / std::sqrt(2.0));
    }
  }

  // Level and correlation from the differences (outliers kept out only when excluded).
  std::vector<double> a_terms, b_terms;
  for (int i = 1; i < n; ++i) {
    if (out[i] || out[i - 1]) continue;
    const double d = residual[i] - residual[i - 1];
    a_terms.push_back(d * d);
    if (i >= 2 && !out[i - 2]) b_terms.push_back(d * (residual[i - 1] - residual[i - 2]));
  }
  if (a_terms.size() < 8 || b_terms.size() < 8) return result;
  double a = 0.0, b = 0.0;
  for (double value : a_terms) a += value;
  for (double value : b_terms) b += value;
  a /= a_terms.size();
  b /= b_terms.size();
  if (!(a > 0.0)) return result;
  // A correlation near 1 is a random walk, not AR(1); it is kept inside (-0.95, 0.98).
  const double rho = std::clamp(1.0 + 2.0 * b / a, -0.95, 0.98);
  const double variance = a / (2.0 * (1.0 - rho));
  result.correlation = rho;
  result.variance_ratio = variance / stated_variance;

  // d(ratio)/d(A, B) and d(rho)/d(A, B), at the moments of the model being judged.
  auto gradients = [&](double s2, double r, Eigen::Vector2d* level, Eigen::Vector2d* corr) {
    const double ea = 2.0 * s2 * (1.0 - r);
    const double eb = -s2 * (1.0 - r) * (1.0 - r);
    *level = Eigen::Vector2d(-ea / (2.0 * eb), ea * ea / (4.0 * eb * eb)) / stated_variance;
    *corr = Eigen::Vector2d(-2.0 * eb / (ea * ea), 2.0 / ea);
  };
  const double count = static_cast<double>(a_terms.size());
  Eigen::Matrix2d covariance;
  if (heavy_tails) {
    // The sample's own covariance of (d_i^2, d_i d_{i-1}), with their first lags.
    const size_t m = std::min(a_terms.size() - 1, b_terms.size());
    Eigen::Matrix2d sum = Eigen::Matrix2d::Zero();
    for (int lag = 0; lag <= 3; ++lag) {
      Eigen::Matrix2d gamma = Eigen::Matrix2d::Zero();
      for (size_t i = lag; i < m; ++i) {
        const Eigen::Vector2d now(a_terms[i + 1] - a, b_terms[i] - b);
        const Eigen::Vector2d before(a_terms[i + 1 - lag] - a, b_terms[i - lag] - b);
        gamma += now * before.transpose();
      }
      gamma /= static_cast<double>(m);
      sum += lag == 0 ? gamma : Eigen::Matrix2d(gamma + gamma.transpose());
    }
    covariance = sum / count;
    result.moments_from_sample = true;
  }
  Eigen::Vector2d level, corr;
  // The test of the level: under "the stated variance, with the correlation seen".
  gradients(stated_variance, rho, &level, &corr);
  const Eigen::Matrix2d null_level =
      heavy_tails ? covariance : Eigen::Matrix2d(MomentCovariance(stated_variance, rho) / count);
  result.level_z = (result.variance_ratio - 1.0) / std::sqrt(level.dot(null_level * level));
  result.level_p = TwoSidedNormalTail(result.level_z);
  // The test of the correlation: under white noise of the variance seen.
  gradients(variance, 0.0, &level, &corr);
  const Eigen::Matrix2d null_white =
      heavy_tails ? covariance : Eigen::Matrix2d(MomentCovariance(variance, 0.0) / count);
  result.correlation_z = rho / std::sqrt(corr.dot(null_white * corr));
  result.correlation_p = TwoSidedNormalTail(result.correlation_z);
  // The reported spreads, at the estimates.
  gradients(variance, rho, &level, &corr);
  const Eigen::Matrix2d at_estimate =
      heavy_tails ? covariance : Eigen::Matrix2d(MomentCovariance(variance, rho) / count);
  result.variance_ratio_stddev = std::sqrt(level.dot(at_estimate * level));
  result.correlation_stddev = std::sqrt(corr.dot(at_estimate * corr));
  return result;
}

}  // namespace accelcal
