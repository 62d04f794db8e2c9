#ifndef ACCELCAL_MODELS_NOISE_MODEL_H_
#define ACCELCAL_MODELS_NOISE_MODEL_H_

// How the noise of one sensing axis is modelled across consecutive samples
// (docs/noise-models.md). Two things ask it: the tilt-test residuals, to be whitened (a
// chi-square and its differences mean something only for whitened residuals), and dead
// reckoning, for what the run's noise does to the endpoint.
//
//   white   e_i independent, N(0, sigma^2);
//   AR(1)   e_i = rho e_{i-1} + w_i, w_i ~ N(0, sigma^2 (1 - rho^2)): a first-order
//           Gauss-Markov process sampled at the sensor's rate, marginal variance sigma^2,
//           correlation rho^|i-j| between samples i and j.
//
// Whitening: w_0 = e_0 / sigma and w_i = (e_i - rho e_{i-1}) / (sigma sqrt(1 - rho^2)) are
// independent N(0, 1), and sum_i w_i^2 is the exact Gaussian -2 log-likelihood up to a
// constant, so chi-square differences between models keep their meaning. Samples set
// aside as outliers carry no weight, and the sample after one starts afresh (as if first).
//
// The tilt test has no clock, so the correlation is per sample; the run is taken to be
// sampled at the rate of the test, and its noise to have the same rho.

#include <algorithm>
#include <cmath>
#include <vector>

namespace accelcal {

struct AxisNoise {
  double variance = 0.0;      // marginal sigma^2, (m/s^2)^2
  double correlation = 0.0;   // rho of consecutive samples, in (-1, 1); 0 is white
  std::vector<int> outliers;  // tilt-test samples set aside, ascending

  bool IsOutlier(int sample) const {
    return std::binary_search(outliers.begin(), outliers.end(), sample);
  }

  // w_i = current e_i - previous e_{i-1} (both 0 for an outlier).
  struct Whitening {
    double current = 0.0;
    double previous = 0.0;
  };
  // The whitening of sample i, knowing whether i and i - 1 are outliers.
  Whitening WhiteningAt(int sample, bool outlier, bool previous_outlier) const {
    if (outlier) return {};
    const double sigma = std::sqrt(variance);
    if (sample == 0 || previous_outlier || correlation == 0.0) return {1.0 / sigma, 0.0};
    const double innovation = sigma * std::sqrt(1.0 - correlation * correlation);
    return {1.0 / innovation, correlation / innovation};
  }

  // Every sample's whitening, in order.
  std::vector<Whitening> WhiteningOf(int samples) const {
    std::vector<Whitening> weights(std::max(0, samples));
    std::vector<char> outlier(weights.size(), 0);
    for (const int i : outliers) {
      if (i >= 0 && i < samples) outlier[i] = 1;
    }
    for (int i = 0; i < samples; ++i) {
      weights[i] = WhiteningAt(i, outlier[i] != 0, i > 0 && outlier[i - 1] != 0);
    }
    return weights;
  }

  // The whitened sequence of residuals e (m/s^2); outliers give 0.
  std::vector<double> Whiten(const std::vector<double>& residual) const {
    const int n = static_cast<int>(residual.size());
    const std::vector<Whitening> weights = WhiteningOf(n);
    std::vector<double> white(n);
    for (int i = 0; i < n; ++i) {
      white[i] =
          weights[i].current * residual[i] - (i > 0 ? weights[i].previous * residual[i - 1] : 0.0);
    }
    return white;
  }

  int InlierCount(int samples) const {
    int inside = 0;
    for (const int i : outliers) inside += i >= 0 && i < samples;
    return samples - inside;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_NOISE_MODEL_H_
