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
