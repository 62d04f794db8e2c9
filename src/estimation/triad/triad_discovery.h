#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_DISCOVERY_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_DISCOVERY_H_

// Does the triad's 9-parameter model explain a multi-position log; if not, what is missing,
// is it an effect the model knows (models/triad_effect_list.h), can the data tell candidates
// apart, and what remains? The two-axis discovery's procedure (estimation/tilt_table/discovery.h)
// on the triad geometry, with the same four verdicts. alpha is shared as there: a null session gets
// any verdict but "explained" with probability at most alpha (tests/triad_discovery_test.cc
// measures it on simulated sessions). In order:
//
// 1. Noise of the pose means, alpha/4. The fit weights each pose mean by a noise model: white
//    (s_k^2 / N_p, from the within-pose variance) unless the caller offers a coloured one
//    (e.g. the Allan variance of the log at each pose's duration,
//    estimation/statistics/allan_variance.h) together with the p-value of white noise against it
//    from the within-pose data alone; rejected at alpha/4, the coloured model is the noise model of
//    every fit after it.
// 2. Effects, alpha/2. Every registered effect that static poses can determine is a candidate,
//    one coefficient at a time (scale_nonlinearity_x, offset_drift_y, ...). Forward
//    selection: each candidate is scored by the chi-square it removes, as an F test against
//    the extended model's own residual scatter (F(1, dof)), so that a noise model that
//    understates the variance makes effects harder to name, not easier; Holm among those
//    left; the strongest rejected is added; repeat. Effects static poses cannot determine
//    (gravity_error, cross_axis) are fitted once to show it: the rank check names what absorbs
//    them, and they are reported as untestable with that name. A candidate whose fit would
//    leave no degree of freedom (a session of 10 poses or fewer), or whose fit fails, is not
//    tested either, and is listed as not testable with why.
// 3. What the final model leaves, alpha/4, Holm, named by its shape: the chi-square of the fit
//    against its degrees of freedom, the correlation of consecutive poses' residuals (either sign:
//    a slow wander, or residuals that alternate), and the shapes of triad_shape_checks.h
//    (orientation by power, time, a step, one pose, full scale), each with its class and advice.
//    The flagged ones are named strongest first: by BIC, a shape alone against offsets that jump
//    from pose to pose (the chi-square's excess with no shape), the rest when they stand beyond
//    those named (docs/triad-discovery.md, section 3). When the scatter is flagged, its size: the
//    per-pose offset wander omega_k that would account for it (the log's unit and m/s^2). The
//    chi-square's lower tail is tested too, at alpha/4 of its own, and reported as a note beside
//    the verdict (the sigmas are conservative), not a verdict.
// 4. Ambiguity: each found effect swapped for every other candidate; one that fits within
//    ambiguity_delta_chi2 (in units of the residual scatter) cannot be told apart from it.
// 5. The gain: leave-poses-out cross-validation (poses dealt to folds in time order, so that
//    every fold spans the session): each held-out pose's direction fitted with the training
//    fit's parameters, its whitened chi-square (1 degree of freedom: 3 residuals, 2 direction
//    unknowns) averaged over the poses, for the baseline and the final model.

#include <array>
#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/discovery/check.h"
#include "estimation/discovery/verdict.h"
#include "estimation/triad/triad_ml_calibration.h"

namespace accelcal {

// The pose means' errors correlated across poses (issue 33, item 4; built from the Allan terms by
// estimation/triad/triad_pose_noise.h, which states the model): per axis k, a pose mean's error
// is an independent part plus the mean over the pose of a bank of Gauss-Markov processes of
// variance process_variance[k] each at the correlation times correlation_s (the bias
// instability B_k as flicker noise, shared by every pose of the session and correlated by the
// time between them). Empty: none.
struct TriadPoseCorrelation {
  std::vector<double> correlation_s;
  std::array<double, 3> process_variance{};  // unit^2, each process of the bank
  std::array<double, 3> white_density{};     // N_k, unit/sqrt(Hz)
  std::array<double, 3> random_walk{};       // K_k, unit sqrt(Hz)
  std::array<double, 3> sample_variance{};   // s_k^2, the pooled within-pose variance, unit^2
  bool empty() const { return correlation_s.empty(); }
};

// A coloured noise model of the pose means, offered to step 1.
struct TriadNoiseCandidate {
  std::vector<std::array<double, 3>> pose_mean_variance;  // per pose and axis, unit^2
  double white_p_value = 1.0;  // of white noise against it, from the within-pose data
  std::string description;     // what it is, for the report
  // When set, the pose means' scatter is judged under it (the chi-square, its lower tail, the
  // lag-1 check and the effects' F tests), whenever the coloured model is chosen; the fits
  // themselves keep pose_mean_variance as their weights.
  TriadPoseCorrelation correlation;
};

struct TriadDiscoveryOptions {
  double alpha = 0.01;
  TriadMlOptions fit;                  // gravity, initial guess, solver; its effects must be empty
  TriadNoiseCandidate coloured_noise;  // empty pose_mean_variance: white noise only
  int cross_validation_folds = 5;      // 0: skip
  int max_effects = 6;
  double ambiguity_delta_chi2 = 6.0;
  // A candidate beside an effect found that gains p <= partner_alpha and moves the effect by
  // partner_shift_sigma or more, or one of whose sigmas beyond its estimate would move it by
  // partner_reach_sigma or more, is a partner: cannot tell apart
  // (PartnerOptions, estimation/discovery/selection.h).
  double partner_alpha = 0.1;
  double partner_shift_sigma = 1.5;
  double partner_reach_sigma = 3.0;
  std::string unit = "count";  // the log's unit, for the effects' units
  std::array<double, 3> gain_mps2_per_unit{{1.0, 1.0, 1.0}};  // to state omega in m/s^2
};

// One coefficient scored at one step of forward selection.
struct TriadCandidateScore {
  int step = 0;
  int coefficient = 0;  // index into TriadEffectCoefficientList()
  std::string name;
  double estimate = 0.0;
  double stddev = 0.0;
  double delta_chi2 = 0.0;
  double f = 0.0;
  double p_value = 1.0;
  bool significant = false;  // rejected by Holm at this step
};

struct TriadFoundEffect {
  int coefficient = 0;
  std::string name;
  std::string unit;
  double estimate = 0.0;  // in the final model
  double stddev = 0.0;
  double delta_chi2 = 0.0;  // the final model's chi-square gain over it without this effect
  double p_value = 1.0;     // F(1, dof) of that gain
  int step = 0;             // forward step that added it
};

// An effect discovery did not test, and why: one static poses cannot determine (with what
// the rank check found absorbing it), or a candidate coefficient the poses left no degree of
// freedom to test, or whose fit failed (confounded_with and rank_check empty then).
struct TriadUntestable {
  std::string effect;           // the effect, or the candidate coefficient
  std::string confounded_with;  // the registration's statement
  std::string rank_check;       // what the fit with it said
  std::string reason;           // why it is not tested, in words
};

struct TriadAmbiguity {
  std::string effect;
  std::string alternative;
  double delta_chi2 = 0.0;  // the alternative model's chi-square minus the final model's
  bool beside = false;      // the alternative is the effect with a partner beside it
  std::string replaces;     // not empty: the partner is in this effect's place, and moves `effect`
  std::string text;         // the two in words, as the verdict says them
};

struct TriadCrossValidation {
  int folds = 0;
  int poses = 0;
  double baseline = 0.0;  // mean held-out chi-square per pose (1 for a right model)
  double final_model = 0.0;
};

struct TriadDiscoveryResult {
  Verdict verdict_code = Verdict::kExplained;
  std::string verdict;  // the verdict line, in words
  TriadMlResult white;  // 9 parameters, white noise
  bool coloured_noise = false;
  std::string noise_note;  // what step 1 decided, in words
  TriadMlResult baseline;  // 9 parameters, the noise model chosen
  std::vector<TriadCandidateScore> candidates;
  std::vector<TriadFoundEffect> effects;
  std::vector<TriadUntestable> untestable;
  TriadMlResult final_fit;
  // "chi2", "pose_lag1_correlation", then the shapes (triad_shape_checks.h).
  std::vector<ResidualCheck> checks;
  // What remains in words, strongest first (WhatRemains of each named check, then a line for the
  // flagged checks that are parts of shapes already named), and which checks those are.
  std::vector<std::string> remaining;
  std::vector<int> remaining_checks;  // indices into checks
  // The effects forward selection found that the shape named first explains as well (the shape
  // alone fits better, by BIC, than the shape with them): found, but not kept in the verdict.
  std::vector<std::string> explained_by_shape;
  // The chi-square's other tail ("chi2_lower_tail"), at alpha/4 and outside the verdict: pose
  // means that scatter less than the noise model says. Nothing is missing from the model then,
  // but the noise model overstates a pose mean's variance (noise anti-correlated within a pose,
  // or variance that averages out), and the sigmas are conservative by about sqrt(chi2/dof).
  ResidualCheck noise_overstated;
  std::array<double, 3> pose_wander{};  // omega_k, the log's unit (0 when nothing remains)
  std::vector<TriadAmbiguity> ambiguities;
  TriadCrossValidation cross_validation;
};

// Fails only when the baseline cannot be fitted (CalibrateTriadMl's refusals).
Status DiscoverTriad(const std::vector<TriadPoseMean>& poses, const TriadDiscoveryOptions& options,
                     TriadDiscoveryResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_DISCOVERY_H_
