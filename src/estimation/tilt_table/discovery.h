#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_DISCOVERY_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_DISCOVERY_H_

// Does the baseline explain the data; if not, what is missing, is it in the catalogue,
// and can the data tell the candidates apart? Three families of tests share alpha (Holm
// within each, Bonferroni across), so that on null data any verdict but "explained" comes
// with probability at most alpha (docs/discovery.md measures it). In order:
//
// 1. Noise, alpha/4 (estimation/statistics/noise_analysis.h, docs/noise-models.md): per axis, from
//    local differences of the baseline's residuals, outliers (set aside by index), heavy
//    tails, the level and the AR(1) correlation. What it finds is the noise model of every
//    fit after it (models/noise_model.h): whitening, the samples set aside, the run's
//    endpoint covariance. With outliers or correlation the baseline is refitted under it
//    before the run is tied to a landmark.
// 2. Effects, alpha/2: forward selection (score every candidate by the chi-square it would
//    remove, Holm among those left, add the strongest, refit in Ceres, re-decide the
//    landmark tie), then backward elimination against the grown model, alternating until
//    neither changes the model.
// 3. Checks of what the final model leaves, alpha/4 (estimation/tilt_table/residual_checks.h):
//    theta harmonics, a curved trend, a step, the turn direction, clipping near full scale,
//    one held position, lag-1 correlation, a portmanteau, the endpoint.
//    Flagged shapes (and a baseline step that explains by BIC as much as every named
//    effect) are nuisance columns: an effect they explain is dropped. What remains is
//    described strongest first, each shape only if it stands once those before it are
//    allowed for.
// 4. Ambiguity: each effect swapped for every other candidate, and for theta-harmonic
//    shapes outside the catalogue; alternatives that fit about as well are reported with
//    what would separate them.
// 5. Heavy tails: the final model refitted with a Huber loss, sandwich covariance.
// 6. The gain: delta chi2 and BIC per effect, the endpoint and landmark posterior before
//    and after, k-fold cross-validation against its null value. Then the verdict.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"
#include "estimation/discovery/verdict.h"
#include "estimation/statistics/diagnostics.h"
#include "estimation/statistics/noise_analysis.h"
#include "estimation/tilt_table/baseline_parameters.h"
#include "estimation/tilt_table/joint_estimator.h"
#include "estimation/tilt_table/landmark_decision.h"
#include "estimation/tilt_table/residual_checks.h"
#include "estimation/tilt_table/trajectory.h"
#include "models/noise_model.h"

namespace accelcal {

struct DiscoveryOptions {
  // The whole procedure's family-wise error rate: a null dataset gets any verdict but
  // "explained" with probability at most alpha (docs/discovery.md measures it).
  double alpha = 0.01;
  double gravity_mps2 = 9.8;
  int theta_bins = 36;
  int ljung_box_lags = 20;
  int cross_validation_folds = 5;  // 0: skip
  int max_effects = 6;
  int num_threads = 1;
  int max_harmonic = 6;  // the residual checks' theta harmonics
  // Two candidates whose models' chi-squares differ by less than this (a likelihood ratio
  // below exp(3) = 20) explain the data about equally well.
  double ambiguity_delta_chi2 = 6.0;
  // A candidate beside an effect found (FindPartners, estimation/discovery/selection.h) is
  // reported with it when it gains p <= partner_alpha and moves the effect's estimate by at
  // least partner_shift_sigma of the effect's sigma as fitted: the data cannot rule it out, and
  // the effect's estimate would carry its signal; or when, one of its sigmas beyond its
  // estimate, it would move the effect by partner_reach_sigma or more (the design leaves it
  // that much room). Also a candidate in another effect's place that fits about as well.
  double partner_alpha = 0.1;
  double partner_shift_sigma = 2.0;
  double partner_reach_sigma = 3.0;
};

// What the noise analysis found on one axis beyond a wrong level (which is
// noise_variance_k among the effects).
struct NoiseFinding {
  enum class Kind { kCorrelation, kOutliers, kHeavyTails };
  Kind kind = Kind::kCorrelation;
  int axis = 0;
  double estimate = 0.0;  // the correlation, the outlier count, or the excess kurtosis
  double stddev = 0.0;    // the correlation's (0 for the others)
  double p_value = 1.0;
  std::vector<int> samples;  // kOutliers: the samples set aside
  std::string description;
};
const char* NoiseFindingName(NoiseFinding::Kind kind);  // "noise_correlation", ...

// Effects of the final model that another candidate would replace at about the same fit.
struct Ambiguity {
  Parameter effect;  // in the final model
  double effect_estimate = 0.0;
  double effect_stddev = 0.0;
  struct Alternative {
    Parameter effect;
    double estimate = 0.0;  // in the model with it instead (a shape: its amplitude)
    double stddev = 0.0;
    double delta_chi2 = 0.0;  // its model's chi-square minus the final model's
    // Not empty: the alternative is a shape outside the catalogue ("x: 3-theta harmonic"),
    // not `effect`.
    std::string shape;
    // A partner (FindPartners) moves this one's estimate: `effect` beside it (delta_chi2 is
    // then minus the partner's gain), or `effect` in the place of `replaces`, another effect of
    // the final model it looks alike in this design. This one's estimate in that model, and the
    // p-value of the partner's gain (beside) or of what it explains in the place of `replaces`.
    bool beside = false;
    std::optional<Parameter> replaces;
    double effect_estimate_with = 0.0;
    double effect_stddev_with = 0.0;
    double p_value = 1.0;
    double reach_sigma = 0.0;  // beside: PartnerOptions::reach_sigma's measure
    std::string note;          // beside: "with the run tied to C" when that model ties it elsewhere
    bool Partner() const { return beside || replaces.has_value(); }
    std::string Name() const { return shape.empty() ? Info(effect).name : shape; }
    std::string Unit() const { return shape.empty() ? Info(effect).unit : "m/s^2"; }
  };
  std::vector<Alternative> alternatives;
  std::string separation;  // what would tell them apart
  // The effect and its alternatives in words, as the verdict says them ("bias_drift_x = ... with
  // nonorthogonality, or bias_drift_x = ... with angle_offset = ... in its place (delta chi2
  // ...)").
  std::string text;
};

// What the final model's effects owe to the landmark the run is tied to. A run effect
// (run_bias_shift_x, ...) moves the endpoint, so it can pay for a tie to the wrong landmark;
// its estimate, and whether it is needed at all, then depend on the tie. A calibration effect
// can pay too, through the bias and scale the run shares with the test. The final model is
// refitted with the run tied to every landmark (JointOptions::Landmark::kAuto): a tie's
// posterior is its likelihood under the final model, its effects free, over the other ties'
// (equal priors). Every tie whose posterior is at least kTiePosteriorReported is kept, with the
// estimates under it of the run effects and of every other effect that a kept tie moves by
// kTieShiftSigma of its sigma or more, and the run effects' joint chi-square there (the same
// model without the run effects, tied to the same landmark, minus with them).
inline constexpr double kTiePosteriorReported = 0.01;
inline constexpr double kTieShiftSigma = 2.0;
struct TieAlternative {
  std::string landmark;
  double posterior = 0.0;
  bool tied = false;              // the tie of the reported estimates
  std::vector<double> estimates;  // per TieDependence::effects
  std::vector<double> stddevs;
  double delta_chi2 = 0.0;  // what the run effects gain under this tie
  double p_value = 1.0;     // chi-square on as many degrees of freedom as run effects
  bool needed = true;       // p_value <= the verdict's alpha (true without run effects)
};
struct TieDependence {
  // The final model's effects that depend on the tie (every run effect, and those a plausible
  // tie moves); empty: nothing depends on the tie.
  std::vector<Parameter> effects;
  std::vector<TieAlternative> ties;  // the tied landmark first, then by posterior
  // Whether the final model has a run effect (every one is among `effects`).
  bool HasRunEffects() const {
    for (const Parameter effect : effects)
      if (ActsOnlyInRun(effect)) return true;
    return false;
  }
  // Whether another tie than the one taken is plausible (posterior >= kTiePosteriorReported).
  bool Depends() const { return ties.size() > 1; }
  // Whether a plausible tie needs no run effect: the data cannot say whether the run has one.
  bool Undecided() const {
    for (const TieAlternative& tie : ties) {
      if (!tie.needed) return true;
    }
    return false;
  }
};

struct AxisDiagnostics {
  NoiseLevelTest noise;
  bool noise_flagged = false;
  double chi2 = 0.0;  // baseline residuals against the stated variance
  int dof = 0;
  WhitenessTest whiteness;
  NormalityTest normality;
  std::vector<ResidualBin> bins;      // baseline residual against theta
  std::vector<double> bin_signature;  // extended minus baseline prediction, per bin
};

struct CandidateScore {
  int step = 0;
  Parameter effect;
  double delta_chi2 = 0.0;
  double p_value = 1.0;
  bool significant = false;  // rejected by Holm at this step
};

// An effect of the final model. Every figure is against the final model: delta_chi2 is the
// chi-square the final model gains over the same model without this effect (same landmark
// tie), p_value its chi-square(1) tail, bic_change the BIC of the final model minus that of
// the model without it. The figures at the moment forward selection added it are kept as
// history (selection_step, selection_delta_chi2, selection_p_value).
struct DiscoveredEffect {
  Parameter effect;
  double estimate = 0.0;  // in the final model (noise_variance_k: the variance ratio)
  double stddev = 0.0;
  double p_value = 1.0;
  double delta_chi2 = 0.0;  // noise_variance_k: z^2 of its noise-level test
  double bic_change = 0.0;  // negative: the effect pays for its parameter
  int selection_step = 0;   // forward step that added it (0: the noise tests)
  double selection_delta_chi2 = 0.0;
  double selection_p_value = 1.0;
};

// One change of the model, in order: forward selection adds an effect, backward elimination
// drops one that the grown model no longer needs (tested against the model of that moment).
struct SelectionEvent {
  // kDropped: the grown model no longer needs it; kDroppedForShape: not needed once the
  // structure the residual checks found (outside the catalogue) is allowed for.
  enum class Kind { kAdded, kDropped, kDroppedForShape };
  Kind kind = Kind::kAdded;
  Parameter effect;
  double delta_chi2 = 0.0;  // what it removed when added, or what it still removed when dropped
  double p_value = 1.0;
  std::string landmark;  // the landmark the run was tied to when it happened
};

struct CrossValidation {
  int folds = 0;
  // Mean whitened squared prediction error of the held-out samples (1 for a right model).
  double baseline = 0.0;
  double extended = 0.0;
  // What the extended model's figure would be if the model and its noise model were right:
  // 1 + p / (rows (1 - 1/folds)) for p parameters seen by the test, and its spread
  // sqrt(2 / rows); z = (extended - null_mean) / null_stddev.
  double null_mean = 1.0;
  double null_stddev = 0.0;
  double z = 0.0;
};

struct DiscoveryResult {
  Verdict verdict_code = Verdict::kExplained;
  BaselineFit baseline;
  std::array<AxisDiagnostics, 2> axes;
  std::array<double, 2> noise_variance_used{};  // stated, or estimated when flagged
  std::array<NoiseAnalysis, 2> noise_analysis;  // of the baseline's residuals
  std::array<AxisNoise, 2> noise_model;         // the noise model of the final fit
  std::vector<NoiseFinding> noise_findings;
  bool robust_fit = false;  // heavy tails: the final estimates are Huber's, sandwich covariance
  DeadReckoningResult baseline_trajectory;
  LandmarkDecision baseline_decision;
  std::string tied_landmark;  // the landmark the run is tied to in step 3 (or empty)
  std::string landmark_note;
  JointResult baseline_joint;  // no effect, run tied
  std::vector<CandidateScore> candidates;
  std::vector<DiscoveredEffect> effects;
  std::vector<SelectionEvent> history;
  JointResult extended;
  DeadReckoningResult extended_trajectory;
  LandmarkDecision extended_decision;
  CrossValidation cross_validation;
  // The checks of what the final model leaves (Holm within their share of alpha), and what
  // remains in words: the flagged checks that stand beyond the stronger shapes, strongest
  // first, each as WhatRemains (its description, then its advice); then, when some flagged
  // checks are parts of those shapes, one line naming them. remaining_checks[i] is the index
  // in `checks` of remaining[i] (the last line, naming the parts, has none).
  std::vector<ResidualCheck> checks;
  std::vector<std::string> remaining;
  std::vector<int> remaining_checks;
  std::vector<Ambiguity> ambiguities;
  TieDependence tie_dependence;
  // The final model's tilt-test residuals (m/s^2, measured minus predicted), per axis, in
  // sample order, for the plots of what remains against theta and against time.
  std::array<std::vector<double>, 2> final_residuals;
  std::string verdict;  // the verdict line, in words
};

Status Discover(const CalibrationTest& test, const VehicleRun& run, const RunConditions& conditions,
                const std::vector<Landmark>& landmarks, const DiscoveryOptions& options,
                DiscoveryResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_DISCOVERY_H_
