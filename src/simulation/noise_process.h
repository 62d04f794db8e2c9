#ifndef ACCELCAL_SIMULATION_NOISE_PROCESS_H_
#define ACCELCAL_SIMULATION_NOISE_PROCESS_H_

// Simulated accelerometer noise of known Allan variance, to check the Allan estimator and fit
// (estimation/statistics/allan_variance.h) against truth, and to bootstrap its fit
// (studies/allan_study.h). One axis, sampled every tau0 s, the sum of independent processes:
//   white:         w_i ~ N(0, N^2 / tau0), N the density in unit/sqrt(Hz);
//   random walk:   r_i = r_{i-1} + e_i, e_i ~ N(0, K^2 tau0), r_0 = e_0, K in unit sqrt(Hz);
//   Gauss-Markov:  g_i = phi g_{i-1} + sqrt(1 - phi^2) q u_i, phi = exp(-tau0 / T_c), u_i ~ N(0,1),
//                  stationary from the start (g_0 ~ N(0, q^2)), any number of them: one is a
//                  first-order approximation of bias instability, whose Allan deviation peaks
//                  near tau = 1.9 T_c; a bank of equal q at geometrically spaced T_c has a flat
//                  Allan deviation between its extreme T_c (flicker noise's).
// The exact Allan variance (the components' add) of the sampled series at m samples per cluster
// (not the continuous formulas, which differ at small m):
//   white:        N^2 / (m tau0)
//   random walk:  K^2 tau0 (2 m^2 + 1) / (6 m)   (-> K^2 tau / 3)
//   Gauss-Markov: (Var S_m - Cov(S_m, S'_m)) / m^2 with S, S' the sums of two adjacent clusters,
//                 Var S_m = q^2 sum_{|k|<m} (m - |k|) phi^|k|,
//                 Cov = q^2 sum_{j=1}^{2m-1} (m - |j - m|) phi^j.

#include <vector>

#include "simulation/random.h"

namespace accelcal {

struct NoiseProcessParameters {
  double sample_period_s = 0.01;  // tau0
  double white_density = 0.0;     // N, unit/sqrt(Hz)
  double random_walk = 0.0;       // K, unit sqrt(Hz)
  struct Markov {
    double stddev = 0.0;         // q, unit
    double correlation_s = 1.0;  // T_c
  };
  std::vector<Markov> markov;
};

// n samples; the same seed and stream give the same series on any machine.
std::vector<double> SimulateNoiseProcess(const NoiseProcessParameters& parameters, long long n,
                                         RandomSource* random);

// The exact Allan variance (the components' add) of the simulated series at cluster size m >= 1,
// unit^2.
double NoiseProcessAllanVariance(const NoiseProcessParameters& parameters, long long m);

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_NOISE_PROCESS_H_
