#ifndef ACCELCAL_STUDIES_TRIAD_DISCOVERY_STUDY_H_
#define ACCELCAL_STUDIES_TRIAD_DISCOVERY_STUDY_H_

// Does the triad's discovery (estimation/triad/triad_discovery.h) hold its level on whole
// simulated sessions, and how often does it name an effect that is there (issue 33, item 4)?
// Each session is a log sample by sample (simulation/triad_log_simulator.h): `poses` holds of
// `hold_s` in random directions (at least 30 degrees apart), turned between them over `turn_s`,
// every sample with white noise of `noise_stddev` counts; with flicker noise too when
// `flicker_b` is set: per axis, a bank of Gauss-Markov processes of equal size at correlation
// times from `flicker_min_s` to `flicker_max_s` spaced by 4 (simulation/noise_process.h), one
// continuous series over the whole session (holds and turns), sized so that the bank's Allan
// variance at the geometric mean of the band is 0.441 B^2 (the flicker floor of Allan terms B,
// Allan deviation 0.664 B), and with a linear offset drift when `offset_drift` is set. The
// outputs are rounded to whole counts. Each session is calibrated on its true holds as
// `calibrate_imu --mode=ml` calibrates a log (CalibrateTriadSessionOnIntervals: the Allan model
// of the pose means chosen by the white-noise test, discovery at `alpha`).
//
// Per session: the verdict, whether the coloured noise model was chosen, the effects named, and
// whether anything remained ("unexplained"). On sessions with nothing hidden but the noise, a
// false discovery is anything beyond the noise: an effect named, or a verdict of unexplained or
// cannot_tell_apart ("missing: coloured noise of the pose means" is right on flicker sessions).
// Its rate should be at most alpha; the band is alpha + 2 binomial sd.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "models/triad.h"

namespace accelcal {

struct TriadDiscoveryStudyOptions {
  int sessions = 400;
  uint64_t seed = 1;
  int poses = 38;
  double hold_s = 8.0;
  double turn_s = 5.5;
  double rate_hz = 100.0;
  std::array<double, 3> noise_stddev{{3.3, 3.2, 3.25}};  // white, per sample, counts
  std::array<double, 3> flicker_b{};                     // bias instability B, counts; 0: none
  double flicker_min_s = 0.02;
  double flicker_max_s = 1400.0;
  std::array<double, 3> offset_drift{};  // counts/s, simulated (hidden unless discovery names it)
  double alpha = 0.01;
  double gravity_mps2 = 9.81744;
  TriadParameters truth{};  // XsensLikeTriad() when left zero
  int threads = 0;
  ProgressFn progress;  // per finished session
};

// The Gauss-Markov bank's per-process standard deviation (counts) for bias instability B.
double FlickerBankStddev(double b, double min_s, double max_s, double sample_period_s);

struct TriadDiscoveryStudyResult {
  int sessions_ok = 0;
  int sessions_failed = 0;
  std::string first_failure;
  std::array<int, 4> verdicts{};     // explained, missing, unexplained, cannot_tell_apart
  int coloured_noise = 0;            // sessions whose pose means the Allan model weighted
  int effect_named = 0;              // sessions with at least one effect found
  int unexplained = 0;               // sessions where something remained
  int beyond_noise = 0;              // effect named, unexplained or cannot_tell_apart
  std::array<int, 3> drift_found{};  // offset_drift_x/y/z found (power when simulated)
  double mean_chi2_per_dof = 0.0;    // the final model's, over the sessions
  // The Allan terms the sessions' poses gave (triad_pose_noise.h), mean over the sessions.
  std::array<double, 3> mean_fitted_n{};
  std::array<double, 3> mean_fitted_b{};
  std::array<double, 3> mean_fitted_k{};
  double beyond_noise_rate = 0.0;
  double level_band = 0.0;  // alpha + 2 sqrt(alpha (1 - alpha) / sessions)
  bool level_held = false;  // beyond_noise_rate <= level_band (meaningful with nothing hidden)
  double seconds = 0.0;
  int threads = 1;
};

Status RunTriadDiscoveryStudy(const TriadDiscoveryStudyOptions& options,
                              TriadDiscoveryStudyResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_STUDIES_TRIAD_DISCOVERY_STUDY_H_
