#ifndef ACCELCAL_STUDIES_TRIAD_MONTE_CARLO_H_
#define ACCELCAL_STUDIES_TRIAD_MONTE_CARLO_H_

// Is the maximum-likelihood triad calibration's reported uncertainty right (issue 20, 5)?
// A fixed pose set (the covariance is conditional on the poses) is simulated `trials` times
// with fresh white noise (simulation/triad_simulator.h) and calibrated each time
// (estimation/triad/triad_ml_calibration.h). Per parameter, over the N trials that succeed:
//
//   spread        the standard deviation of the estimates (the Monte Carlo truth about sigma)
//   mean sigma    the mean of the reported sigma
//   ratio         mean sigma / spread; its relative standard error is ~1/sqrt(2 (N - 1))
//                 (2.2% for N = 1000), so the issue's [0.9, 1.1] is a ~4.5 sd band
//   bias          (mean estimate - truth) / mean sigma, standard error ~1/sqrt(N)
//   coverage      the fraction of trials with |estimate - truth| <= k sigma, k = 1, 2, 3,
//                 expected 68.27, 95.45, 99.73%, binomial sd sqrt(P (1 - P) / N)
//
// and for the fit statistic: the mean chi2/dof (expected 1, sd sqrt(2 / dof) / sqrt(N)) and
// the fraction of trials with p < 0.01 (expected 1%).
//
// Verdict: every ratio in [0.9, 1.1] (widened to 1 +- 3 of its sd when that is wider, i.e.
// below ~500 trials), every coverage and the p < 0.01 fraction within 3 binomial sd of what
// is expected, and no failed trial. A claim needs at least 1000 trials.
//
// Degenerate pose sets: the first session is calibrated first; when the calibration refuses
// it (the poses cannot determine the model), the study stops there and reports the refusal,
// the unidentifiable parameters and the poses to add; it runs no trials.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "models/triad.h"
#include "studies/sigma_check.h"

namespace accelcal {

enum class TriadPoseSet {
  kRandom,  // `poses` directions uniform on the sphere, drawn once from the seed
  kPlanar,  // `poses` directions on the great circle orthogonal to x (turned about x only)
  kSix,     // +x, -x, +y, -y, +z, -z (imucal's six holds)
  kFew,     // one pose fewer than the Jacobian's rank needs: parameters - 1 random directions
};

const std::vector<std::string>& TriadPoseSetNames();  // "random", "planar", "six", "few"
Status ParseTriadPoseSet(const std::string& name, TriadPoseSet* pose_set);
const char* TriadPoseSetName(TriadPoseSet pose_set);

// A triad like imu_tk's Xsens unit: angles (yz, zy, zx) = (0.0035, -0.009, 0.021) rad,
// gains 1/(414.5, 412.0, 414.6) (m/s^2)/count, offsets (33124, 33275, 32364) counts.
TriadParameters XsensLikeTriad();
// The second-order scale terms simulated by default when they are estimated:
// (2e-4, -1e-4, 3e-4) 1/(m/s^2), i.e. 8 to 23 counts at 1 g along the axis.
TriadScaleNonlinearity ExampleScaleNonlinearity();

struct TriadMonteCarloOptions {
  int trials = 1000;
  uint64_t seed = 1;
  TriadPoseSet pose_set = TriadPoseSet::kRandom;
  int poses = 30;  // random and planar; six and few fix their own count
  int samples_per_pose = 100;
  std::array<double, 3> noise_stddev{{3.0, 3.0, 3.0}};  // per sample, counts
  double gravity_mps2 = 9.81744;
  TriadParameters truth = XsensLikeTriad();
  TriadScaleNonlinearity truth_scale_nonlinearity{};  // simulated (1/(m/s^2))
  bool scale_nonlinearity = false;                    // estimated: the 12-parameter fit
  int threads = 0;      // 0: all cores; the results do not depend on it
  ProgressFn progress;  // per finished trial
};

// The fit starts from angles 0, k2 0, and every gain and offset at the mean of the truth's
// three (a datasheet-like nominal guess, hundreds of counts from the offsets).
TriadParameters TriadStudyInitialGuess(const TriadParameters& truth);

// One parameter: its sigma against the spread of its estimates (studies/sigma_check.h's figures).
struct TriadParameterStudy : SigmaCheck {
  std::string name;
  std::string unit;
  double truth = 0.0;
};

struct TriadMonteCarloResult {
  int parameter_count = 9;
  std::vector<std::array<double, 3>> directions;  // the pose set (unit specific force)
  // Set when the first session was refused; then nothing below it is.
  bool refused = false;
  std::string refusal;
  std::vector<std::string> unidentifiable;
  std::vector<std::array<double, 3>> suggested_directions;

  int trials_ok = 0;
  int trials_failed = 0;
  std::string first_failure;  // its message, with the trial index
  std::vector<TriadParameterStudy> parameters;
  int degrees_of_freedom = 0;
  double chi2_per_dof_mean = 0.0;
  double chi2_per_dof_mean_stderr = 0.0;  // sqrt(2 / dof) / sqrt(N)
  double p_below_001 = 0.0;               // fraction of trials with p < 0.01
  double p_below_001_stderr = 0.0;        // sqrt(0.01 * 0.99 / N)
  static constexpr std::array<double, 3> kExpectedCoverage = kNormalCoverage;

  bool claim_possible = false;        // trials_ok >= 1000
  bool passed = false;                // every check below held
  std::vector<std::string> failures;  // one line per failed check, naming the parameter
  double seconds = 0.0;
  int threads = 1;
};

// Fails only on options no study can run (a non-positive count, noise or gravity); a pose
// set that cannot determine the model is a result (refused), not an error.
Status RunTriadMonteCarlo(const TriadMonteCarloOptions& options, TriadMonteCarloResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_TRIAD_MONTE_CARLO_H_
