#ifndef ACCELCAL_ESTIMATION_STATISTICS_DIAGNOSTICS_H_
#define ACCELCAL_ESTIMATION_STATISTICS_DIAGNOSTICS_H_

// What a fit leaves behind, judged against the stated noise: the noise level itself
// (von Neumann's successive-difference estimator, immune to smooth unmodelled effects),
// the residual's mean as a function of theta (binned, with its standard error),
// whiteness (Ljung-Box) and normality (Jarque-Bera).

#include <vector>

namespace accelcal {

// The noise variance of a sequence read from its successive differences:
// S = sum_i (e_i - e_{i-1})^2 has mean 2 (N-1) sigma^2 and, for white Gaussian noise,
// variance about 12 N sigma^4; effects that vary slowly from sample to sample barely
// touch it. `ratio` is the estimated variance over the stated one.
struct NoiseLevelTest {
  double ratio = 1.0;
  double ratio_stddev = 0.0;
  double z = 0.0;        // (ratio - 1) / its standard deviation under the statement
  double p_value = 1.0;  // two-sided, normal approximation (N in the thousands)
};
NoiseLevelTest TestNoiseLevel(const std::vector<double>& residual, double stated_variance);

struct ResidualBin {
  double theta_center_rad = 0.0;
  int count = 0;
  double mean = 0.0;            // m/s^2
  double standard_error = 0.0;  // sigma / sqrt(count), from the noise variance used
};
// Residuals binned by theta into `bins` equal intervals over the observed range.
std::vector<ResidualBin> BinByTheta(const std::vector<double>& theta_rad,
                                    const std::vector<double>& residual, int bins,
                                    double noise_variance);

struct WhitenessTest {
  int lags = 0;
  double q = 0.0;        // Ljung-Box statistic
  double p_value = 1.0;  // chi-square with `lags` dof
};
WhitenessTest LjungBox(const std::vector<double>& residual, int lags);

struct NormalityTest {
  double skewness = 0.0;
  double excess_kurtosis = 0.0;
  double jarque_bera = 0.0;
  double p_value = 1.0;  // chi-square with 2 dof
};
NormalityTest JarqueBera(const std::vector<double>& residual);

// Holm's step-down thresholds: the k-th smallest of m p-values is compared with
// alpha / (m - k). Returns, for each input p-value, whether it is rejected.
std::vector<bool> HolmRejections(const std::vector<double>& p_values, double alpha);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_STATISTICS_DIAGNOSTICS_H_
