#ifndef ACCELCAL_ESTIMATION_STATISTICS_NOISE_ANALYSIS_H_
#define ACCELCAL_ESTIMATION_STATISTICS_NOISE_ANALYSIS_H_

// What one axis's residual sequence says about its noise, read from local differences so
// that smooth unmodelled effects (which change little from one sample to the next) cannot
// pass for noise, and noise cannot pass for an effect (docs/noise-models.md):
//
//   level and correlation  with d_i = e_i - e_{i-1}, A = mean d_i^2 and B = mean d_i d_{i-1};
//                          for AR(1) noise (models/noise_model.h) of marginal variance
//                          s^2, E A = 2 s^2 (1 - rho) and E B = -s^2 (1 - rho)^2, so
//                          rho = 1 + 2 B / A and s^2 = A^2 / (-4 B). White noise gives
//                          rho = 0 and s^2 = A / 2 (von Neumann), and both stay right when
//                          the noise is correlated, where A / 2 alone reads rho = 0.6 as a
//                          variance 2.5 times too small. Their standard deviations are the
//                          delta method's under the fitted AR(1) (Gaussian), or from the
//                          sample's own moments when the tails are heavy;
//   outliers               s_i = e_i - median(e_{i-3..i+3} without e_i), scaled by its
//                          median absolute deviation: the largest |s_i| against the
//                          Bonferroni bound over the samples;
//   tails                  the excess kurtosis of the pair differences e_{2j+1} - e_{2j}
//                          (independent and Gaussian under any Gaussian noise), tested
//                          one-sided with the Anscombe-Glynn transformation, on the samples
//                          left after the candidate outliers.

#include <vector>

namespace accelcal {

struct NoiseAnalysisOptions {
  // A sample is a candidate outlier when its score's two-sided normal tail, times the
  // number of samples, is below this.
  double outlier_alpha = 1e-3;
};

struct NoiseAnalysis {
  int samples = 0;
  // Marginal variance over the stated one, and the correlation of consecutive samples.
  double variance_ratio = 1.0;
  double variance_ratio_stddev = 0.0;
  double level_z = 0.0;
  double level_p = 1.0;  // two-sided, against ratio 1
  double correlation = 0.0;
  double correlation_stddev = 0.0;
  double correlation_z = 0.0;
  double correlation_p = 1.0;  // two-sided, against 0
  // Outliers.
  double largest_score = 0.0;           // the largest |s_i| in robust sigma
  double outlier_p = 1.0;               // Bonferroni over the samples
  std::vector<int> outlier_candidates;  // ascending
  // Tails, after the candidates.
  double excess_kurtosis = 0.0;
  double kurtosis_z = 0.0;
  double kurtosis_p = 1.0;           // one-sided: heavier than Gaussian
  bool moments_from_sample = false;  // the sds above come from the sample's moments
};

// `residual` in sample order, m/s^2; `excluded` samples (ascending) are left out of every
// statistic. With `heavy_tails` the level and correlation sds are the sample's own.
NoiseAnalysis AnalyzeNoise(const std::vector<double>& residual, double stated_variance,
                           const std::vector<int>& excluded, bool heavy_tails,
                           const NoiseAnalysisOptions& options = NoiseAnalysisOptions());

// The two-sided standard normal tail, P(|Z| > |z|).
double TwoSidedNormalTail(double z);
// The z with TwoSidedNormalTail(z) = p (p in (0, 1)).
double TwoSidedNormalQuantile(double p);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_STATISTICS_NOISE_ANALYSIS_H_
