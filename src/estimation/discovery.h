#ifndef ACCELCAL_ESTIMATION_DISCOVERY_H_
#define ACCELCAL_ESTIMATION_DISCOVERY_H_

// Does the baseline explain the data, and if not, which effect of the catalogue is
// missing? In order:
//
// 1. Fit the baseline and look at what it leaves: per axis, the noise level against the
//    stated variance (von Neumann's successive differences, immune to smooth effects),
//    chi-square, the residual against theta in bins, whiteness (Ljung-Box) and normality
//    (Jarque-Bera); and the endpoint against the landmarks.
// 2. Noise first: an axis whose noise level is off (two-sided, Holm over the two axes at
//    alpha/2) is reported as noise_variance_k, and its estimated variance is used for
//    everything after, so a wrong statement does not pass for an effect.
// 3. Forward selection: tie the run to the most probable landmark, score every candidate
//    effect (the chi-square it would remove, one dof each), keep those Holm rejects at
//    alpha/2 among the candidates left, add the strongest, refit the joint problem in
//    Ceres, and repeat until none is significant. (alpha/2 for each of the two families
//    keeps the whole procedure's family-wise error rate at alpha.)
// 4. The gain: delta chi2 and BIC per effect, the shift of each baseline parameter in its
//    sigma, the endpoint and landmark posterior before and after, and k-fold
//    cross-validation over contiguous blocks of the tilt test.

#include <array>
#include <string>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"
#include "estimation/baseline_parameters.h"
#include "estimation/diagnostics.h"
#include "estimation/joint_estimator.h"
#include "estimation/landmark_decision.h"
#include "estimation/trajectory.h"

namespace accelcal {

struct DiscoveryOptions {
  double alpha = 0.01;
  double gravity_mps2 = 9.8;
  int theta_bins = 36;
  int ljung_box_lags = 20;
  int cross_validation_folds = 5;  // 0: skip
  int max_effects = 6;
  int num_threads = 1;
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

struct DiscoveredEffect {
  Parameter effect;
  double estimate = 0.0;  // in the final model (noise_variance_k: the variance ratio)
  double stddev = 0.0;
  double p_value = 1.0;     // when selected
  double delta_chi2 = 0.0;  // chi-square removed by the refit (noise_variance_k: z^2)
  double bic_change = 0.0;  // BIC after minus before (negative: better)
};

struct CrossValidation {
  int folds = 0;
  // Mean whitened squared prediction error of the held-out samples (1 for a right model).
  double baseline = 0.0;
  double extended = 0.0;
};

struct DiscoveryResult {
  BaselineFit baseline;
  std::array<AxisDiagnostics, 2> axes;
  std::array<double, 2> noise_variance_used{};  // stated, or estimated when flagged
  DeadReckoningResult baseline_trajectory;
  LandmarkDecision baseline_decision;
  std::string tied_landmark;  // the landmark the run is tied to in step 3 (or empty)
  std::string landmark_note;
  JointResult baseline_joint;  // no effect, run tied
  std::vector<CandidateScore> candidates;
  std::vector<DiscoveredEffect> effects;
  JointResult extended;
  DeadReckoningResult extended_trajectory;
  LandmarkDecision extended_decision;
  CrossValidation cross_validation;
  std::string verdict;
};

Status Discover(const CalibrationTest& test, const VehicleRun& run, const RunConditions& conditions,
                const std::vector<Landmark>& landmarks, const DiscoveryOptions& options,
                DiscoveryResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_DISCOVERY_H_
