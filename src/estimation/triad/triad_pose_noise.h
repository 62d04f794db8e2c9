#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_POSE_NOISE_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_POSE_NOISE_H_

// The coloured noise model of a triad's pose means that discovery is offered
// (estimation/triad/triad_discovery.h, step 1), from the log's own static data: per axis, the Allan
// variance of the poses' samples pooled (estimation/statistics/allan_variance.h), its three terms
// fitted (N, B, K, weighted least squares), and the variance of each pose's mean from them at the
// pose's duration, sigma^2_model(T_p) (AllanPoseMeanVariance).
//
// White noise against it, from the within-pose data alone: at the largest octave tau no longer
// than half the median pose, the pooled Allan variance against white noise of the pooled
// per-sample variance s_k^2 (s_k^2 / m at m samples), an upper-tail chi-square test with the
// white-noise equivalent degrees of freedom (AllanEquivalentDof summed over the poses); the
// three axes' p-values combined by Bonferroni (3 times the smallest, at most 1).
//
// Quantisation, added to either model (TriadMlOptions::quantisation_variance). An output rounded
// to a step q, y = q round((mu + e) / q) with e ~ N(0, sigma^2) white, has per-sample variance
// s^2 that the pooled within-pose variance measures, and a mean E[y] = mu + b(mu) whose bias does
// not average down: with the rounding error as its Fourier series and the Gaussian's
// characteristic function,
//   b(mu) = sum_{j>=1} (-1)^j (q / (pi j)) exp(-2 pi^2 j^2 sigma^2 / q^2) sin(2 pi j mu / q).
// Over poses whose means fall anywhere on the grid (mu uniform modulo q), a pose mean of N
// samples has error variance s^2/N + B, with
//   B(sigma, q) = q^2 / (2 pi^2) sum_{j>=1} exp(-4 pi^2 j^2 sigma^2 / q^2) / j^2
// (q^2/12 at sigma = 0, 0.037 q^2 at sigma = 0.1 q, 0.0015 q^2 at 0.3 q, 5e-6 q^2 at 0.5 q and
// below 1e-150 q^2 at 3 q: Sheppard's dither). sigma is the noise before rounding; the pooled
// s^2 of the rounded samples, averaged over mu in the same way, is
//   s^2 = sigma^2 + q^2/12 - B(sigma, q),
// increasing in sigma, solved for it per axis. q is the output's step (OutputSteps: the smallest
// nonzero change between samples; tiny for a float log, so B = 0). Where B matters, the Allan
// model is not offered to auto (its white test assumes Gaussian samples; see the .cc).

#include <array>
#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/statistics/allan_variance.h"
#include "estimation/triad/static_intervals.h"
#include "estimation/triad/triad_discovery.h"

namespace accelcal {

struct TriadPoseNoise {
  TriadNoiseCandidate candidate;
  std::array<AllanNoiseTerms, 3> terms{};  // per axis, in the log's unit
  double test_tau_s = 0.0;                 // the tau white noise was tested at
  std::array<double, 3> avar_ratio{};      // sigma^2(tau) / (s_k^2 / m) there (1 for white)
  std::array<double, 3> white_p_value{};   // per axis
  // Quantisation (above), per axis, in the log's unit: the step q, the noise before rounding
  // sigma, and B, added to every pose mean's variance.
  std::array<double, 3> output_step{};
  std::array<double, 3> unrounded_stddev{};
  std::array<double, 3> quantisation_variance{};
  // B is at least 1 % of a median pose mean's white variance s^2/N on some axis (shown then).
  bool quantisation_material = false;
};

// B(sigma, q) above, from sigma^2; q^2/12 at sigma = 0, 0 for q = 0.
double QuantisationBiasVariance(double noise_variance, double step);

// sigma^2 from the rounded samples' variance s^2, solving s^2 = sigma^2 + q^2/12 - B(sigma, q).
double UnroundedNoiseVariance(double rounded_variance, double step);

// Poses: the intervals the pose means were taken from, in the same order. Fails, saying why,
// when the poses are too short for an Allan variance at two or more taus.
Status TriadPoseNoiseFromLog(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                             const std::vector<TriadPoseMean>& poses, TriadPoseNoise* noise);

// The pose means' covariance across poses (issue 33, item 4; TriadPoseCorrelation in
// triad_discovery.h), from the Allan terms of each axis. The bias instability B is flicker noise:
// its Allan deviation stays at 0.664 B over every tau, so poses minutes apart share one slowly
// wandering offset, and their means are not independent. It is modelled as a bank of
// Gauss-Markov processes of equal variance q^2 at correlation times T_i from a quarter of the
// median pose to the first at least the session's span (first to last pose mid-time), spaced by
// 4; q^2 such that the bank's Allan variance at the geometric mean of its ends is 0.441 B^2 (one
// process's: q^2 (T/tau)^2 (2 tau/T - 3 + 4 e^(-tau/T) - e^(-2 tau/T))). Per process, the means
// of poses p and q (durations T_p, T_q, centres dt apart, not overlapping) have covariance
// q^2 b_p b_q e^(-dt/T) with b = sinh(x/2) / (x/2), x = T_p / T, and a pose's own mean variance
// q^2 a(x), a(x) = 2 (x - 1 + e^(-x)) / x^2. The white and random-walk terms stay independent
// per pose, as in sigma^2(T): max(N^2/T_p + K^2 T_p/3, s^2/N_p) (a random walk fitted within
// poses of seconds, extrapolated as one walk over minutes, overstated the scatter of simulated
// flicker sessions tenfold). Empty when B is 0 on every axis.
TriadPoseCorrelation TriadPoseCorrelationFromTerms(const std::array<AllanNoiseTerms, 3>& terms,
                                                   const std::vector<TriadPoseMean>& poses,
                                                   const std::array<double, 3>& sample_variance);

// The chi-square of `fit` (CalibrateTriadMl's, at its parameters, effects and directions) with
// the pose means judged under `correlation`, plus `added_variance` per axis and pose (the
// quantisation term): each pose's residual is reduced to the one component its own direction
// cannot absorb (q_p, normal to the direction's two columns of the pose's Jacobian: the
// directions are eliminated exactly, as in generalised least squares with per-pose nuisance
// unknowns), these are whitened in time order by a Kalman filter over the bank's 3 x processes
// states (linear in the poses), and one Gauss-Newton step of the estimated parameters under the
// whitened model is taken from the fit (the fit weights the means by their own variances only;
// the step reaches the generalised least-squares minimum to second order). chi2 is that minimum,
// on the fit's degrees of freedom; `innovations` (may be null) the whitened residuals after the
// step, in the poses' time order, independent N(0, 1) under the model.
Status TriadCorrelatedChi2(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                           const TriadPoseCorrelation& correlation,
                           const std::array<double, 3>& added_variance, double gravity_mps2,
                           double* chi2, std::vector<double>* innovations);

// Which noise model weights the pose means of a calibration (calibrate_imu --noise).
enum class TriadNoiseChoice { kAuto, kWhite, kAllan };
Status ParseTriadNoiseChoice(const std::string& text, TriadNoiseChoice* choice);

// The Allan model when the poses allow one (noise->candidate empty otherwise), the quantisation
// term in either case, and whether the calibration uses the Allan model: kAllan always (failing
// when the poses are too short), kAuto when white noise is rejected against it at alpha/4
// (discovery's share for the noise), kWhite never.
Status SelectTriadPoseNoise(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                            const std::vector<TriadPoseMean>& poses, TriadNoiseChoice choice,
                            double alpha, TriadPoseNoise* noise, bool* use_allan);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_POSE_NOISE_H_
