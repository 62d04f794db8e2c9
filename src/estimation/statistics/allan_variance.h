#ifndef ACCELCAL_ESTIMATION_STATISTICS_ALLAN_VARIANCE_H_
#define ACCELCAL_ESTIMATION_STATISTICS_ALLAN_VARIANCE_H_

// The noise of an accelerometer axis from its static data (issue 21, item 1): the overlapping
// Allan variance with chi-square confidence intervals, the standard noise terms fitted to it,
// and the variance of a pose's mean that follows.
//
// Allan variance. For samples y_0 .. y_{n-1} taken every tau0 s (one static segment; several
// segments are pooled by adding their sums and counts, no difference ever spans two), cluster
// time tau = m tau0, and cumulative sums S_k = y_0 + ... + y_{k-1}:
//   sigma^2(tau) = 1 / (2 m^2 (n - 2m + 1)) sum_{k=0}^{n-2m} (S_{k+2m} - 2 S_{k+m} + S_k)^2,
// half the mean square difference of adjacent m-sample means, over every start k (overlapping
// estimator, O(n) per tau). m runs over the octaves 1, 2, 4, ... while 4 m <= n of the longest
// segment (a segment too short for an m is left out of that m). Unit: the data's unit squared.
//
// Confidence. The overlapping estimate is treated as sigma^2 chi2_edf / edf, with the equivalent
// degrees of freedom of the noise that dominates sigma^2(tau) in the fitted model (the
// approximations of IEEE Std 1139 / Howe, Allan and Barnes 1981, as Greenhall and Riley state
// them for overlapping estimates; N = n + 1 phase points):
//   white noise (white FM):        edf = (3 (N-1) / (2m) - 2 (N-2) / N) 4 m^2 / (4 m^2 + 5)
//   bias instability (flicker FM): edf = 2 (N-2)^2 / (2.3 N - 4.9) for m = 1,
//                                        5 N^2 / (4 m (N + 3m)) otherwise
//   random walk (random-walk FM):  edf = (N-2) / m ((N-1)^2 - 3m (N-1) + 4 m^2) / (N-3)^2
// summed over the segments. The interval at level 1 - alpha is
//   [edf sigma^2 / chi2_edf(1 - alpha/2), edf sigma^2 / chi2_edf(alpha/2)].
//
// Noise terms (IEEE Std 952 notation, for an accelerometer; "unit" is the data's unit, m/s^2
// once converted):
//   sigma^2(tau) = N^2 / tau + (2 ln 2 / pi) B^2 + K^2 tau / 3
//   N: white noise density (velocity random walk), unit/sqrt(Hz) ((m/s^2)/sqrt(Hz) = m/s/sqrt(s));
//   B: bias instability, unit; the Allan deviation's floor is sqrt(2 ln 2 / pi) B = 0.664 B;
//   K: acceleration random walk, unit sqrt(Hz) ((m/s^2)/sqrt(s)).
// sigma^2 is linear in (N^2, B^2, K^2), so the fit is a weighted linear least squares in those
// three coefficients: weight 1 / var(sigma^2_hat(tau)) = edf / (2 sigma^2_model(tau)^2),
// iterated with the model (the measured sigma^2 in the weight would bias the fit low).
//
// Confidence of the terms. The least squares covariance (A^T W A)^-1 treats the Allan variances
// at different tau as independent, which they are not (the same samples enter every tau): its
// 95% intervals covered N only 85% and K 83% of the time (400 series of 20000 samples). And K^2
// (like B^2) is poorly determined and skewed: with a correct spread, a symmetric interval still
// misses high when the estimate falls low (86.5% for a stated 95%). The intervals callers should
// state are therefore the parametric bootstrap's test inversion (studies/allan_study.h): the
// values of a term for which the observed coefficient is in neither alpha/2 tail of the
// coefficients refitted on series simulated with that value. A term whose interval reaches 0 is
// not resolved: its value is max(0, fitted) and its upper bound is what to state.
//
// Variance of a mean. A pose is an average over T seconds, and the calibration weighs its mean
// by the variance of that average. For white noise it is N^2 / T = sigma^2(T). For the other
// terms the variance of a T-average about the process's own mean is not defined (random walk,
// flicker) or depends on a correlation time the data rarely show; what a calibration sees is how
// the means of poses differ from one another, and sigma^2(T) is by definition half the mean
// square difference of two adjacent T-averages. So the variance of a pose mean is taken as
// sigma^2_model(T) = N^2 / T + (2 ln 2 / pi) B^2 + K^2 T / 3: exact for white noise, and for the
// others the variance each of two independent means would need to differ as adjacent ones do.
// Poses further apart than adjacent differ more under random walk (K^2 times their separation);
// that is not in it.

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "common/status.h"

namespace accelcal {

// The noise that dominates sigma^2(tau), which sets its degrees of freedom.
enum class AllanNoiseKind { kWhite, kBiasInstability, kRandomWalk };
const char* AllanNoiseKindName(AllanNoiseKind kind);

// Equivalent degrees of freedom of one segment of n samples at cluster size m (formulas above),
// at least 1.
double AllanEquivalentDof(AllanNoiseKind kind, long long n, long long m);

struct AllanCurve;

// Whether a segment of n samples enters the point at cluster size m: at least 4 clusters.
inline bool AllanSegmentUsed(long long n, long long m) { return 4 * m <= n; }

// The degrees of freedom of `curve`'s point at cluster size m: the sum over the segments that
// enter it (AllanSegmentUsed), as ComputeAllanVariance averages them.
double AllanCurveDof(AllanNoiseKind kind, const AllanCurve& curve, long long m);

struct AllanPoint {
  long long cluster_samples = 0;       // m
  double tau_s = 0.0;                  // m tau0
  double avar = 0.0;                   // sigma^2(tau), unit^2
  long long difference_count = 0;      // overlapping differences, summed over segments
  long long independent_clusters = 0;  // floor(n / m), summed over segments
  // Filled by FitAllanNoise from the fitted model (white noise until then):
  AllanNoiseKind dominant = AllanNoiseKind::kWhite;
  double edf = 0.0;
  double avar_low = 0.0;  // confidence interval of sigma^2 at AllanOptions::confidence
  double avar_high = 0.0;
};

struct AllanCurve {
  double sample_period_s = 0.0;            // tau0
  std::vector<long long> segment_samples;  // n per segment
  std::vector<AllanPoint> points;          // octave-spaced m, increasing
};

struct AllanOptions {
  double confidence = 0.95;  // of the Allan variance intervals and of the terms' intervals
  bool fit_white = true;
  bool fit_bias_instability = true;
  bool fit_random_walk = true;
  int iterations = 6;  // of the reweighting
};

// The Allan variance of `segments` (each uniformly sampled every sample_period_s, in one unit;
// their means need not agree). Intervals from white-noise degrees of freedom. Fails, saying
// what to do, when no segment has 4 samples or a value is not finite.
Status ComputeAllanVariance(const std::vector<std::vector<double>>& segments,
                            double sample_period_s, const AllanOptions& options, AllanCurve* curve);

// ComputeAllanVariance with the segments handed over one at a time (a long log's static poses
// read back one by one, issue 36, item 2): the same curve to the last bit, holding one segment's
// cumulative sums at a time instead of every segment. Start with the segments' lengths in the
// order they will be added, then Add each, then Finish; the same failures at the same points.
//
// AddStreamed hands a segment over in pieces instead (a still log of hours, 10^8 samples, is one
// segment, issue 49, item 1): the same sums to the last bit (the same arithmetic in the same
// order), from memory that does not depend on the segment's length. The cumulative sums S_k are
// made in one pass in order, after a first pass for the mean; S_{k+m} and S_k are taken from a
// ring of the last 2^19 sums (8 MB) when the lag (m or 2m) fits in it, else from a cursor that
// reads the segment again in order, lag samples behind, and makes the same sums (one per such
// lag: the longest taus of a segment of more than 2^18 samples). So: two reads of the segment
// plus one per long lag, each in order, and O(n) work per point.
class AllanVarianceAccumulator {
 public:
  // Fills values[0 .. count) with samples [first, first + count) of the segment (the same values
  // at every call; calls for increasing `first` within each of several interleaved passes).
  using SegmentReader = std::function<Status(long long first, long long count, double* values)>;

  Status Start(double sample_period_s, const AllanOptions& options,
               const std::vector<long long>& segment_samples);
  Status Add(const std::vector<double>& segment);
  Status AddStreamed(long long samples, const SegmentReader& read);
  Status Finish(AllanCurve* curve);

  // The cumulative sums AddStreamed holds (2^19 unless set; a power of 2, at least 2), so that a
  // test can send short segments' lags to the cursors. Call before Start.
  void SetHeldSums(long long sums) { held_sums_ = sums; }

 private:
  long long held_sums_ = 1 << 19;
  AllanOptions options_;
  AllanCurve curve_;
  long long longest_ = 0;
  size_t added_ = 0;
  std::vector<long double> totals_;  // sum of squared differences, per point
  std::vector<long double> sums_;    // the segment's cumulative sums
};

// One fitted term: the coefficient of sigma^2 (N^2, B^2 or K^2), its sigma, and the term in its
// own unit with an interval at the options' confidence (from the coefficient's, normal).
struct AllanTerm {
  bool fitted = false;    // asked for
  bool resolved = false;  // coefficient > 0 and its interval excludes 0
  double squared = 0.0;   // N^2, B^2 or K^2 (clamped at 0 when fitted negative)
  double squared_raw = 0.0;
  double squared_stddev = 0.0;
  double value = 0.0;   // N, B or K
  double stddev = 0.0;  // of the value, by the delta method (0 when not resolved)
  double low = 0.0;     // interval of the value
  double high = 0.0;
  // The fitted coefficient is lower than the model gives even with this term at 0 (in the
  // bootstrap's lower alpha/2 tail): the curve falls where the terms cannot; upper bound 0.
  bool below_model = false;
};

struct AllanNoiseFit {
  AllanTerm white;                       // N, unit/sqrt(Hz)
  AllanTerm bias_instability;            // B, unit
  AllanTerm random_walk;                 // K, unit sqrt(Hz)
  std::array<double, 3> coefficients{};  // N^2, B^2, K^2 as fitted (may be negative)
  // "weighted least squares" (normal intervals from its covariance: too narrow, see above) or
  // "parametric bootstrap" (test-inversion intervals, covariance of the refits).
  std::string covariance_method = "weighted least squares";
  int bootstrap_series = 0;  // when the intervals are a bootstrap's
  double chi2 = 0.0;         // sum of w (sigma^2_hat - sigma^2_model)^2
  int dof = 0;               // points - fitted terms
  // The fraction of the bootstrap's series (simulated from the fitted terms) whose chi2 is at
  // least the data's: the taus are correlated, so chi2 does not follow chi2(dof); a small
  // fraction says the terms do not describe the curve, and the intervals assume they do.
  // -1 without a bootstrap.
  double chi2_bootstrap_fraction = -1.0;
  // Covariance of the coefficients N^2, B^2, K^2 (rows/columns of unfitted terms are 0).
  std::array<std::array<double, 3>, 3> covariance{};
};

// Fits the terms the options ask for and fills each point's dominant kind, edf and interval.
// Fails when fewer points than terms remain.
Status FitAllanNoise(const AllanOptions& options, AllanCurve* curve, AllanNoiseFit* fit);

// The fit prepared once for one curve's taus and segments, to fit many vectors of Allan
// variances of that shape exactly as FitAllanNoise fits the curve's own (the bootstrap refits
// thousands, studies/allan_study.h): white-noise weights on the given values first, then
// options.iterations reweightings by the model, in fixed-size arithmetic.
class AllanFitter {
 public:
  AllanFitter(const AllanOptions& options, const AllanCurve& curve);

  // Fails, saying what to do, when there are fewer points than terms + 1 (Fit must not be
  // called then).
  Status Check() const;

  // The coefficients N^2, B^2, K^2 fitted to `avar` (one per point of the curve; 0 for a term
  // not asked for); with term >= 0 (0 N^2, 1 B^2, 2 K^2) that coefficient held at `fixed` and
  // the others fitted: the model closest to the data under that value, which the bootstrap
  // simulates to test it. The final weights into *weights when given. False when singular.
  bool Fit(const double* avar, std::array<double, 3>* coefficients, int term = -1,
           double fixed = 0.0, std::vector<double>* weights = nullptr) const;

  // sum_i weights_i (sigma^2_model(tau_i) - avar_i)^2 with the coefficients as fitted (negative
  // ones included).
  double Chi2(const double* avar, const std::array<double, 3>& coefficients,
              const std::vector<double>& weights) const;

  int points() const { return static_cast<int>(tau_s_.size()); }

  // Octave taus of up to 2^62 samples.
  static constexpr int kMaxFitPoints = 64;

 private:
  std::vector<int> columns_;
  int iterations_ = 0;
  std::vector<double> tau_s_;
  std::vector<std::array<double, 3>> x_;    // regressors per point
  std::vector<std::array<double, 3>> edf_;  // per point, by AllanNoiseKind
};

// The terms' values from fit->coefficients and their sigmas and normal intervals from
// fit->covariance (the least squares intervals).
void SetAllanTermsFromCovariance(const AllanOptions& options, AllanNoiseFit* fit);

// One axis's noise terms in plain numbers, in the unit U of the data they were fitted to.
struct AllanNoiseTerms {
  double white_density = 0.0;     // N, U/sqrt(Hz)
  double bias_instability = 0.0;  // B, U
  double random_walk = 0.0;       // K, U sqrt(Hz)
};

// The fitted terms (a term fitted negative, or not fitted, is 0).
AllanNoiseTerms FittedNoiseTerms(const AllanNoiseFit& fit);

// sigma^2_model(tau) = N^2 / tau + (2 ln 2 / pi) B^2 + K^2 tau / 3, U^2.
double ModelAllanVariance(const AllanNoiseTerms& terms, double tau_s);
double ModelAllanVariance(const AllanNoiseFit& fit, double tau_s);

// The variance of the mean of a pose of duration_s seconds (see "Variance of a mean" above):
// sigma^2_model(duration_s), in U^2 for terms in U (the log's unit when the segments were given
// in it: counts^2 for counts). Per axis; duration_s > 0.
double AllanPoseMeanVariance(const AllanNoiseTerms& terms, double duration_s);

// sqrt(2 ln 2 / pi) = 0.664: the Allan deviation's floor per unit of bias instability.
double BiasInstabilityFactor();

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_STATISTICS_ALLAN_VARIANCE_H_
