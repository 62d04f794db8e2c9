#include "estimation/statistics/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "estimation/statistics/chi_square.h"

namespace accelcal {

NoiseLevelTest TestNoiseLevel(const std::vector<double>& residual, double stated_variance) {
  NoiseLevelTest test;
  const size_t n = residual.size();
  if (n < 3 || !(stated_variance > 0.0)) return test;
  double sum = 0.0;
  for (size_t i = 1; i < n; ++i) sum += std::pow(residual[i] - residual[i - 1], 2);
  test.ratio = sum / (2.0 * (n - 1) * stated_variance);
  // Var(S) = 8 (N-1) sigma^4 + 4 (N-2) sigma^4: neighbouring differences share a sample.
  test.ratio_stddev = std::sqrt(8.0 * (n - 1) + 4.0 * (n - 2)) / (2.0 * (n - 1));
  test.z = (test.ratio - 1.0) / test.ratio_stddev;
  test.p_value = std::erfc(std::abs(test.z) / std::sqrt(2.0));
  return test;
}

std::vector<ResidualBin> BinByTheta(const std::vector<double>& theta_rad,
                                    const std::vector<double>& residual, int bins,
                                    double noise_variance) {
  std::vector<ResidualBin> result(std::max(1, bins));
  if (theta_rad.empty()) return result;
  const auto [low, high] = std::minmax_element(theta_rad.begin(), theta_rad.end());
  const double width = std::max((*high - *low) / result.size(), 1e-12);
  for (size_t i = 0; i < theta_rad.size(); ++i) {
    const size_t bin =
        std::min(result.size() - 1, static_cast<size_t>((theta_rad[i] - *low) / width));
    result[bin].count += 1;
    result[bin].mean += residual[i];
  }
  for (size_t b = 0; b < result.size(); ++b) {
    ResidualBin& bin = result[b];
    bin.theta_center_rad = *low + (b + 0.5) * width;
    if (bin.count > 0) {
      bin.mean /= bin.count;
      bin.standard_error = std::sqrt(noise_variance / bin.count);
    }
  }
  return result;
}

WhitenessTest LjungBox(const std::vector<double>& residual, int lags) {
  WhitenessTest test;
  const size_t n = residual.size();
  test.lags = lags;
  if (n <= static_cast<size_t>(lags) + 1) return test;
  const double mean = std::accumulate(residual.begin(), residual.end(), 0.0) / n;
  double denominator = 0.0;
  for (double e : residual) denominator += (e - mean) * (e - mean);
  for (int k = 1; k <= lags; ++k) {
    double numerator = 0.0;
    for (size_t i = k; i < n; ++i) numerator += (residual[i] - mean) * (residual[i - k] - mean);
    const double rho = numerator / denominator;
    test.q += rho * rho / (n - k);
  }
  test.q *= n * (n + 2.0);
  test.p_value = ChiSquareSurvival(test.q, lags);
  return test;
}

NormalityTest JarqueBera(const std::vector<double>& residual) {
  NormalityTest test;
  const size_t n = residual.size();
  if (n < 8) return test;
  const double mean = std::accumulate(residual.begin(), residual.end(), 0.0) / n;
  double m2 = 0.0, m3 = 0.0, m4 = 0.0;
  for (double e : residual) {
    const double d = e - mean;
    m2 += d * d;
    m3 += d * d * d;
    m4 += d * d * d * d;
  }
  m2 /= n;
  m3 /= n;
  m4 /= n;
  test.skewness = m3 / std::pow(m2, 1.5);
  test.excess_kurtosis = m4 / (m2 * m2) - 3.0;
  test.jarque_bera =
      n / 6.0 * (test.skewness * test.skewness + test.excess_kurtosis * test.excess_kurtosis / 4.0);
  test.p_value = ChiSquareSurvival(test.jarque_bera, 2.0);
  return test;
}

std::vector<bool> HolmRejections(const std::vector<double>& p_values, double alpha) {
  const size_t m = p_values.size();
  std::vector<size_t> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return p_values[a] < p_values[b]; });
  std::vector<bool> rejected(m, false);
  for (size_t k = 0; k < m; ++k) {
    if (!(p_values[order[k]] <= alpha / (m - k))) break;
    rejected[order[k]] = true;
  }
  return rejected;
}

}  // namespace accelcal
