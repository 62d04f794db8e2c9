#include "studies/allan_study.h"

#include <cmath>
#include <vector>

#include "common/format.h"
#include "simulation/random.h"

namespace accelcal {

NoiseProcessParameters AllanModelProcess(const AllanNoiseFit& fit, const AllanCurve& curve) {
  NoiseProcessParameters process;
  process.sample_period_s = curve.sample_period_s;
  process.white_density = fit.white.value;
  process.random_walk = fit.random_walk.value;
  if (fit.bias_instability.value > 0.0 && !curve.points.empty()) {
    const double tau_max_s = curve.points.back().tau_s;
    for (double t_c = curve.sample_period_s / 2.0; t_c <= 2.0 * tau_max_s; t_c *= 4.0)
      process.markov.push_back({1.0, t_c});
    // Scale the bank's unit-q Allan variance at the middle cluster size to the fitted floor.
    const long long middle = curve.points[curve.points.size() / 2].cluster_samples;
    NoiseProcessParameters bank;
    bank.sample_period_s = curve.sample_period_s;
    bank.markov = process.markov;
    const double floor =
        BiasInstabilityFactor() * BiasInstabilityFactor() * fit.bias_instability.squared;
    const double q = std::sqrt(floor / NoiseProcessAllanVariance(bank, middle));
    for (NoiseProcessParameters::Markov& markov : process.markov) markov.stddev = q;
  }
  return process;
}

Status FitAllanNoiseWithBootstrap(const AllanOptions& options,
                                  const AllanBootstrapOptions& bootstrap, AllanCurve* curve,
                                  AllanNoiseFit* fit) {
  ACCELCAL_RETURN_IF_ERROR(FitAllanNoise(options, curve, fit));
  if (bootstrap.series < 2) return Status::Ok();
  const NoiseProcessParameters process = AllanModelProcess(*fit, *curve);
  std::vector<std::array<double, 3>> samples;
  for (int series = 0; series < bootstrap.series; ++series) {
    RandomSource random(bootstrap.seed, static_cast<uint64_t>(series));
    std::vector<std::vector<double>> segments;
    for (long long n : curve->segment_samples)
      segments.push_back(SimulateNoiseProcess(process, n, &random));
    AllanCurve simulated;
    AllanNoiseFit refit;
    ACCELCAL_RETURN_IF_ERROR(
        ComputeAllanVariance(segments, curve->sample_period_s, options, &simulated));
    // A simulated series the fit cannot handle is left out; the count says how many were used.
    if (!FitAllanNoise(options, &simulated, &refit).ok()) continue;
    samples.push_back(refit.coefficients);
  }
  if (samples.size() < 2) {
    return Status::Error(
        StringPrintf("the bootstrap could refit only %zu of %d simulated series; fit fewer terms",
                     samples.size(), bootstrap.series));
  }
  std::array<double, 3> mean{};
  for (const auto& c : samples)
    for (int j = 0; j < 3; ++j) mean[j] += c[j] / static_cast<double>(samples.size());
  fit->covariance = {};
  for (const auto& c : samples) {
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
        fit->covariance[r][k] +=
            (c[r] - mean[r]) * (c[k] - mean[k]) / static_cast<double>(samples.size() - 1);
  }
  fit->covariance_method = "parametric bootstrap";
  fit->bootstrap_series = static_cast<int>(samples.size());
  SetAllanTermsFromCovariance(options, fit);
  return Status::Ok();
}

}  // namespace accelcal
