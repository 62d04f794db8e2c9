#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_POSE_NOISE_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_POSE_NOISE_H_

// The coloured noise model of a triad's pose means that discovery is offered
// (estimation/triad/triad_discovery.h, step 1), from the log's own static data: per axis, the Allan
// variance of the poses' samples pooled (estimation/statistics/allan_variance.h), its three terms fitted
// (N, B, K, weighted least squares), and the variance of each pose's mean from them at the
// pose's duration, sigma^2_model(T_p) (AllanPoseMeanVariance).
//
// White noise against it, from the within-pose data alone: at the largest octave tau no longer
// than half the median pose, the pooled Allan variance against white noise of the pooled
// per-sample variance s_k^2 (s_k^2 / m at m samples), an upper-tail chi-square test with the
// white-noise equivalent degrees of freedom (AllanEquivalentDof summed over the poses); the
// three axes' p-values combined by Bonferroni (3 times the smallest, at most 1).

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
};

// Poses: the intervals the pose means were taken from, in the same order. Fails, saying why,
// when the poses are too short for an Allan variance at two or more taus.
Status TriadPoseNoiseFromLog(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                             const std::vector<TriadPoseMean>& poses, TriadPoseNoise* noise);

// Which noise model weights the pose means of a calibration (calibrate_imu --noise).
enum class TriadNoiseChoice { kAuto, kWhite, kAllan };
Status ParseTriadNoiseChoice(const std::string& text, TriadNoiseChoice* choice);

// The Allan model when the poses allow one (noise->candidate empty otherwise), and whether the
// calibration uses it: kAllan always (failing when the poses are too short), kAuto when white
// noise is rejected against it at alpha/4 (discovery's share for the noise), kWhite never.
Status SelectTriadPoseNoise(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                            const std::vector<TriadPoseMean>& poses, TriadNoiseChoice choice,
                            double alpha, TriadPoseNoise* noise, bool* use_allan);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_POSE_NOISE_H_
