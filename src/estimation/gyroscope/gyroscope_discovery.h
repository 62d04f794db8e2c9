#ifndef ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_DISCOVERY_H_
#define ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_DISCOVERY_H_

// Does the gyroscope's model (models/gyroscope.h: 6 angles, 3 gains, 3 offsets) explain a
// session; if not, is what is missing an effect of models/gyroscope_effect_list.h, can the data
// tell the candidates apart, and what remains? The one discovery procedure (estimation/discovery/
// selection.h) with the gyroscope as a geometry (GyroscopeGeometry in the .cc), the four verdicts
// of estimation/discovery/verdict.h, alpha shared as the triad's (estimation/triad/
// triad_discovery.h):
//
// 1. Noise, alpha/4: a bias wander between poses, when the poses' offsets scatter beyond their
//    white noise (GyroscopeMlOptions::bias_wander_alpha = alpha/4), then the turns' sampling
//    error, when the turns reject the model without it (turn_sampling_alpha = alpha/4); the
//    noise model found is that of every fit after it (held fixed, so that nested fits compare by
//    chi-square).
// 2. Effects, alpha/2: the candidates g_sensitivity (9 coefficients), scale_asymmetry (3) and
//    scale_nonlinearity (3), each tested as one group: the chi-square it removes, chi-square on
//    its coefficients' count; forward selection with Holm, backward elimination (SelectEffects).
// 3. What remains, alpha/4, Holm, on the final model refitted with its own wander (estimated again
//    at alpha/4: an effect found, a g-sensitivity above all, may have been what the baseline's
//    wander stood for): the turns' chi-square against their 2 components each, and, when the
//    final model needs no wander, the rest residuals' against theirs.
// 4. Look-alikes: each effect found swapped for every other candidate; within
//    ambiguity_delta_chi2 (times the residual scatter when above 1) it cannot be told apart.
// Verdict: DecideVerdict(structure remains, look-alikes, effects or a wander found).

#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/discovery/check.h"
#include "estimation/discovery/selection.h"
#include "estimation/discovery/verdict.h"
#include "estimation/gyroscope/gyroscope_ml_calibration.h"
#include "estimation/statistics/parameter_determination.h"
#include "estimation/triad/static_intervals.h"
#include "estimation/triad/triad_ml_calibration.h"

namespace accelcal {

struct GyroscopeDiscoveryOptions {
  double alpha = 0.01;
  GyroscopeMlOptions fit;  // unit, g, start; its effects must be empty
  int max_effects = 3;
  double ambiguity_delta_chi2 = 6.0;
  // The turns' sampling error may be part of the noise model (step 1); false: never.
  bool turn_sampling = true;
  // What the baseline's unknowns must be determined to (gyroscope_determination.h).
  DeterminationThresholds determination;
};

struct GyroscopeEffectScore {
  int step = 0;
  std::string effect;
  double delta_chi2 = 0.0;
  int coefficients = 0;
  double p_value = 1.0;
  bool significant = false;
};

struct GyroscopeFoundEffect {
  std::string effect;
  std::vector<std::string> names;  // its coefficients
  std::vector<double> estimates;   // in the final model
  std::vector<double> stddevs;
  double delta_chi2 = 0.0;  // what the final model loses without it
  double p_value = 1.0;
};

struct GyroscopeLookAlike {
  std::string effect;
  std::string alternative;
  double worse = 0.0;  // the alternative's chi-square minus the final model's
};

struct GyroscopeDiscoveryResult {
  Verdict verdict_code = Verdict::kExplained;
  std::string verdict;               // in words
  GyroscopeMlResult baseline;        // the 12 unknowns, the noise model of step 1
  bool bias_wander = false;          // the baseline's noise model has one
  bool final_bias_wander = false;    // the final model's (estimated again with its effects)
  bool turn_sampling = false;        // the baseline's noise model has the turns' sampling error
  bool final_turn_sampling = false;  // the final model's
  std::string noise_note;
  std::vector<GyroscopeEffectScore> scores;
  std::vector<std::string> not_tested;  // candidate: why
  std::vector<GyroscopeFoundEffect> effects;
  GyroscopeMlResult final_fit;
  std::vector<ResidualCheck> checks;  // "turns_chi2", "rest_chi2"
  std::vector<std::string> remaining;
  std::vector<GyroscopeLookAlike> look_alikes;
  // The 12 unknowns of the model settled on (final_fit when effects were found, else the
  // baseline: the calibration written) the session determines too poorly to vouch for
  // (gyroscope_determination.h); the verdict's text names them after its own words, and the
  // verdict's code is not changed by them (as the accelerometer's is not).
  std::vector<PoorlyDeterminedParameter> poorly_determined;
};

// The candidates, as indices into GyroscopeEffectInfos().
Status DiscoverGyroscope(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                         const TriadMlOptions& accelerometer_options,
                         const TriadMlResult& accelerometer,
                         const GyroscopeDiscoveryOptions& options,
                         GyroscopeDiscoveryResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_DISCOVERY_H_
