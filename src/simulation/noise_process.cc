#include "simulation/noise_process.h"

#include <algorithm>
#include <cmath>

namespace accelcal {

std::vector<double> SimulateNoiseProcess(const NoiseProcessParameters& parameters, long long n,
                                         RandomSource* random) {
  const double tau0 = parameters.sample_period_s;
  const double white_stddev = parameters.white_density / std::sqrt(tau0);
  const double step_stddev = parameters.random_walk * std::sqrt(tau0);
  std::vector<double> y(static_cast<size_t>(std::max(0LL, n)));
  double walk = 0.0;
  for (double& v : y) {
    walk += step_stddev * random->StandardNormal();
    v = white_stddev * random->StandardNormal() + walk;
  }
  for (const NoiseProcessParameters::Markov& markov : parameters.markov) {
    const double phi = std::exp(-tau0 / markov.correlation_s);
    const double drive = std::sqrt(1.0 - phi * phi) * markov.stddev;
    double g = markov.stddev * random->StandardNormal();
    for (size_t i = 0; i < y.size(); ++i) {
      if (i > 0) g = phi * g + drive * random->StandardNormal();
      y[i] += g;
    }
  }
  return y;
}

double NoiseProcessAllanVariance(const NoiseProcessParameters& parameters, long long m) {
  const double tau0 = parameters.sample_period_s;
  const double md = static_cast<double>(m);
  double avar =
      parameters.white_density * parameters.white_density / (md * tau0) +
      parameters.random_walk * parameters.random_walk * tau0 * (2.0 * md * md + 1.0) / (6.0 * md);
  for (const NoiseProcessParameters::Markov& markov : parameters.markov) {
    const double phi = std::exp(-tau0 / markov.correlation_s);
    double variance = md;  // k = 0
    double covariance = 0.0;
    double power = 1.0;  // phi^j
    for (long long j = 1; j <= 2 * m - 1; ++j) {
      power *= phi;
      if (j < m) variance += 2.0 * static_cast<double>(m - j) * power;
      covariance += static_cast<double>(m - std::llabs(j - m)) * power;
    }
    avar += markov.stddev * markov.stddev * (variance - covariance) / (md * md);
  }
  return avar;
}

}  // namespace accelcal
