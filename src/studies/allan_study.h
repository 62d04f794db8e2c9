#ifndef ACCELCAL_STUDIES_ALLAN_STUDY_H_
#define ACCELCAL_STUDIES_ALLAN_STUDY_H_

// The covariance of the Allan noise fit (estimation/allan_variance.h) by parametric bootstrap.
// The weighted least squares covariance treats the Allan variances at different tau as
// independent; they share the samples, and its intervals cover too rarely (85% for a stated
// 95%, tests/allan_variance_test.cc). Here the fitted model is simulated
// (simulation/noise_process.h) with the data's own segment lengths and sample period, the
// Allan variance computed and fitted as for the data, `series` times, and the coefficients'
// sample covariance replaces the fit's; the terms' sigmas and intervals follow from it.
//
// The simulated model: white noise N, random walk K, and for bias instability a bank of
// Gauss-Markov processes of equal q with correlation times tau0/2 * 4^j up to twice the
// longest cluster time, q set so that the bank's exact Allan variance at the geometric middle
// of the fitted taus is (2 ln 2 / pi) B^2 (within the taus it stays within about 20% of flat).

#include <cstdint>

#include "common/status.h"
#include "estimation/allan_variance.h"
#include "simulation/noise_process.h"

namespace accelcal {

struct AllanBootstrapOptions {
  int series = 100;  // 0: keep the least squares covariance
  uint64_t seed = 1;
};

// The process the bootstrap simulates for `fit` on `curve`'s taus.
NoiseProcessParameters AllanModelProcess(const AllanNoiseFit& fit, const AllanCurve& curve);

// FitAllanNoise, then the bootstrap covariance in place of the fit's (fit->covariance_method and
// fit->bootstrap_series say which one it is).
Status FitAllanNoiseWithBootstrap(const AllanOptions& options,
                                  const AllanBootstrapOptions& bootstrap, AllanCurve* curve,
                                  AllanNoiseFit* fit);

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_ALLAN_STUDY_H_
