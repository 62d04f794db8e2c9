#ifndef ACCELCAL_STUDIES_SIGMA_CHECK_H_
#define ACCELCAL_STUDIES_SIGMA_CHECK_H_

// One estimated quantity's reported sigma against the spread of its estimates over N Monte Carlo
// trials, the arithmetic every sigma study shares (studies/triad_monte_carlo.h,
// studies/gyroscope_monte_carlo.h):
//
//   mean, mean sigma     over the trials
//   spread               the estimates' standard deviation (N - 1)
//   ratio                mean sigma / spread, standard error ~ ratio / sqrt(2 (N - 1))
//   bias                 (mean - truth) / mean sigma, standard error spread / sqrt(N) / mean sigma
//   coverage             the fraction of trials with |estimate - truth| <= k sigma, k = 1, 2, 3

#include <algorithm>
#include <array>
#include <cmath>

namespace accelcal {

struct SigmaCheck {
  double mean = 0.0;
  double mean_sigma = 0.0;
  double spread = 0.0;
  double ratio = 0.0;
  double ratio_stderr = 0.0;
  double bias_sigma = 0.0;
  double bias_sigma_stderr = 0.0;
  std::array<double, 3> coverage{};
};

// The normal's coverage at 1, 2, 3 sigma.
constexpr std::array<double, 3> kNormalCoverage = {0.682689492137086, 0.954499736103642,
                                                   0.997300203936740};

// estimate(i) and sigma(i): trial i's, for i in [0, n), n >= 1.
template <typename EstimateAt, typename SigmaAt>
SigmaCheck CheckSigma(int trials, double truth, const EstimateAt& estimate, const SigmaAt& sigma) {
  SigmaCheck check;
  const double n = trials;
  for (int i = 0; i < trials; ++i) {
    check.mean += estimate(i) / n;
    check.mean_sigma += sigma(i) / n;
  }
  double variance = 0.0;
  for (int i = 0; i < trials; ++i) {
    variance += std::pow(estimate(i) - check.mean, 2) / std::max(1.0, n - 1);
    for (int level = 0; level < 3; ++level)
      check.coverage[level] += (std::abs(estimate(i) - truth) <= (level + 1) * sigma(i)) / n;
  }
  check.spread = std::sqrt(variance);
  check.ratio = check.mean_sigma / check.spread;
  check.ratio_stderr = check.ratio / std::sqrt(2.0 * std::max(1.0, n - 1));
  check.bias_sigma = (check.mean - truth) / check.mean_sigma;
  check.bias_sigma_stderr = check.spread / std::sqrt(n) / check.mean_sigma;
  return check;
}

// Whether a fraction over n trials is within `band_sd` binomial standard deviations of `expected`.
inline bool WithinBinomialBand(double fraction, double expected, int n, double band_sd) {
  return std::abs(fraction - expected) <= band_sd * std::sqrt(expected * (1.0 - expected) / n);
}

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_SIGMA_CHECK_H_
