#ifndef ACCELCAL_STUDIES_GYROSCOPE_MONTE_CARLO_H_
#define ACCELCAL_STUDIES_GYROSCOPE_MONTE_CARLO_H_

// Is the gyroscope's maximum-likelihood calibration's reported uncertainty right (issue 32, 4)?
// A fixed hand-held session design (the poses' directions, the turns' yaws, drawn once from the
// seed: the covariance is conditional on them) is simulated `trials` times with fresh noise on
// both sensors (simulation/triad_log_simulator.h), the accelerometer calibrated on the true holds
// (estimation/triad/triad_ml_calibration.h, white noise, from a nominal start), then the gyroscope
// (estimation/gyroscope/gyroscope_ml_calibration.h). Per gyroscope unknown, over the trials that
// succeed: the spread of the estimates, the mean reported sigma, their ratio (relative standard
// error ~1/sqrt(2 (N - 1)), 2.2% at N = 1000), the bias in sigmas and the coverage at 1, 2, 3
// sigma; and the fraction of trials whose gyroscope fit statistic has p < 0.01.
//
// Verdict, as the triad's study (studies/triad_monte_carlo.h): every ratio in [0.9, 1.1]
// (widened to 1 +- 3 sd below ~500 trials), every coverage and the p < 0.01 fraction within 3
// binomial sd, no failed trial; a claim needs at least 1000 trials.
//
// Degenerate designs (turns about too few axes): the first session is calibrated first; when the
// gyroscope's calibration refuses it, the study reports the refusal and runs no trials.

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "estimation/gyroscope/gyroscope_discovery.h"
#include "estimation/gyroscope/gyroscope_ml_calibration.h"
#include "estimation/triad/static_intervals.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "simulation/triad_log_simulator.h"
#include "studies/sigma_check.h"
#include "studies/triad_monte_carlo.h"

namespace accelcal {

enum class GyroscopeTurnSet {
  kRandom,  // directions uniform on the sphere, each turn >= 40 degrees, yaws in +-90 degrees
  kPlanar,  // directions on the great circle normal to x, no yaw: every turn about x. The
            // accelerometer's poses then lie in a plane and it is refused first: poses spread
            // enough for the accelerometer are joined by turns about every axis
};
Status ParseGyroscopeTurnSet(const std::string& name, GyroscopeTurnSet* turn_set);
const char* GyroscopeTurnSetName(GyroscopeTurnSet turn_set);

// A gyroscope like imu_tk's Xsens unit (its imu_tk calibration): gains 1/(4778, 4764, 4774)
// (rad/s)/count, its six angles, offsets (32777, 32460, 32512) counts.
GyroscopeParameters XsensLikeGyroscope();
GyroscopeOffset XsensLikeGyroscopeOffset();

struct GyroscopeSessionDesign {
  GyroscopeTurnSet turn_set = GyroscopeTurnSet::kRandom;
  int poses = 30;
  double hold_s = 4.0;
  double rate_hz = 100.0;
  double turn_s = 1.5;
  double gravity_mps2 = 9.81744;
  std::array<double, 3> accelerometer_noise{{3.0, 3.0, 3.0}};  // counts
  std::array<double, 3> gyroscope_noise{{3.0, 3.0, 3.0}};      // counts
  TriadParameters accelerometer_truth = XsensLikeTriad();
  GyroscopeParameters truth = XsensLikeGyroscope();
  GyroscopeOffset offset = XsensLikeGyroscopeOffset();
  GyroscopeEffectCoefficients effects{};  // simulated
  // The gyroscope's outputs rounded to whole counts (and the fit told so), or continuous (a log
  // already in rad/s or deg/s: truth and noise then in that unit).
  bool gyroscope_in_counts = true;
  // The simulation has no Earth rate; the fit's allowance for it (GyroscopeMlOptions::
  // earth_rate_as_noise) is then off, unless this asks for it (its sigmas are then wider than the
  // spread by design).
  bool earth_rate_allowance = false;
  // Turns that start and stop abruptly (TriadLogSimulationOptions::turn_abruptness), and the
  // fit's estimation of the turns' sampling error (GyroscopeMlOptions::turn_sampling_alpha; 1:
  // whenever the turns scatter beyond the rest of the noise model; 0: never).
  double turn_abruptness = 0.0;
  double turn_sampling_alpha = 0.0;
  // The Earth's rate in the simulated gyroscope at this latitude (and then counted in the fit),
  // and whether the fit is told the latitude (GyroscopeMlOptions::latitude_given).
  bool earth_rate = false;
  double latitude_deg = 59.35;
  bool latitude_known = false;
};

// The simulator's options for a session of the design (both sensors, their truths and noise).
TriadLogSimulationOptions GyroscopeDesignSimulation(const GyroscopeSessionDesign& design);

// The design's holds (directions and yaws), drawn from `seed`.
std::vector<TriadHold> GyroscopeDesignHolds(const GyroscopeSessionDesign& design, uint64_t seed);

// One session simulated with the noise stream `noise_seed`, both sensors calibrated;
// `estimated`: the gyroscope's effect coefficients to estimate.
struct GyroscopeSessionFit {
  TriadSession session;
  std::vector<StaticInterval> intervals;  // the true holds
  TriadMlOptions accelerometer_options;
  TriadMlResult accelerometer;
  GyroscopeMlOptions gyroscope_options;
  GyroscopeMlResult gyroscope;
};
Status SimulateAndCalibrateGyroscope(const GyroscopeSessionDesign& design,
                                     const std::vector<TriadHold>& holds, uint64_t noise_seed,
                                     const std::vector<int>& estimated, GyroscopeSessionFit* fit);

// One unknown: its sigma against the spread of its estimates (studies/sigma_check.h's figures).
struct GyroscopeUnknownStudy : SigmaCheck {
  std::string name;
  std::string unit;
  double truth = 0.0;
  bool ratio_ok = false;
  bool coverage_ok = false;
};

struct GyroscopeMonteCarloOptions {
  GyroscopeSessionDesign design;
  int trials = 1000;
  uint64_t seed = 1;
  std::vector<int> estimated;  // effect coefficients estimated
  // Also run discovery (estimation/gyroscope/gyroscope_discovery.h) at this alpha on every session
  // and count its verdicts: on sessions with nothing simulated beyond the model, the rate of any
  // verdict but "explained" is the false-alarm rate the procedure promises to keep at most alpha;
  // with effects simulated, the rate of finding each is the power. 0: no discovery.
  double discovery_alpha = 0.0;
  int threads = 0;
  ProgressFn progress;
};

struct GyroscopeMonteCarloResult {
  static constexpr std::array<double, 3> kExpectedCoverage = kNormalCoverage;
  bool refused = false;  // the design's first session was refused
  std::string refusal;
  std::vector<std::string> undetermined;
  std::vector<std::string> turn_axes_to_add;
  int trials = 0;
  int succeeded = 0;
  int clipped_turns = 0;      // turns the fits left out as clipped (none in an unclipped design)
  std::string first_failure;  // of a trial
  std::vector<std::string> failures;  // what the verdict found wrong
  std::vector<GyroscopeUnknownStudy> unknowns;
  double mean_chi2_per_dof = 0.0;  // the gyroscope's part
  double p_below_001 = 0.0;
  bool p_ok = false;
  // With discovery: the verdicts' counts (explained, missing, unexplained, cannot_tell_apart),
  // the sessions in which each effect group was found, and the false-alarm verdict: when nothing
  // is simulated, the rate of not-explained within alpha + 2 binomial sd.
  std::array<int, 4> verdicts{};
  std::array<int, kGyroscopeEffectCount> found{};
  // The sessions in which each of discovery's what-remains checks flagged (by name; absent: in
  // none): on null sessions, each check's own false-alarm rate.
  std::map<std::string, int> checks_flagged;
  int discovery_failures = 0;
  bool null_rate_ok = true;
  bool passed = false;          // nothing found wrong
  bool claim_possible = false;  // and at least 1000 trials succeeded
  double seconds = 0.0;
};

Status RunGyroscopeMonteCarlo(const GyroscopeMonteCarloOptions& options,
                              GyroscopeMonteCarloResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_GYROSCOPE_MONTE_CARLO_H_
