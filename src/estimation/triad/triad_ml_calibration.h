#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_ML_CALIBRATION_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_ML_CALIBRATION_H_

// The maximum-likelihood calibration of a triad from its static poses (issue 20, 4(b);
// docs/triad.md):
//
//   minimise 1/2 sum_p sum_k ((ubar_p,k - u_p,k) / sigma_p,k)^2,  u_p = b + K^-1 T^-1 g n_p
//
// over the 9 parameters of models/triad.h and one unit gravity direction n_p per pose
// (2 degrees of freedom each, on ceres::SphereManifold<3>), residuals/triad_pose_residual.h.
//
// Noise model: every sample is the truth plus white noise, independent between samples and
// axes, of one variance s_k^2 per axis for the whole log, estimated pooled over the poses:
//   s_k^2 = sum_p (N_p - 1) s_p,k^2 / sum_p (N_p - 1);
// the mean of pose p then has variance s_k^2 / N_p. 3P residuals, 9 + 2P unknowns,
// P - 9 degrees of freedom.
//
// Solved by Levenberg-Marquardt with the directions eliminated first (Ceres' DENSE_SCHUR: the
// normal equations are an arrow matrix, each step O(P)). Covariance of the 9 parameters: the
// inverse of the information with the directions as nuisance parameters, i.e. of the sensor
// parameters' reduced information (estimation/triad/triad_identifiability.h), the number
// ceres::Covariance over every block gives (to rounding), in O(P). Fit statistic:
// chi2 = sum r^2 on P - 9 degrees of freedom, p = P(chi2_{P-9} > chi2); chi2/dof has mean 1
// and standard deviation sqrt(2/dof) when the noise model holds.
//
// Effects beyond the 9 parameters (models/triad_effect_list.h): options.effects names the
// coefficients to estimate (options.scale_nonlinearity adds the three second-order scale terms
// k2_k); all of them are one block, the others held at zero: 9 + E parameters, P - 9 - E
// degrees of freedom. A coefficient that depends on time (offset_drift_k) is referred to the
// mean of the poses' mid-times.
//
// The noise of a pose mean: by default the white-noise variance above, s_k^2 / N_p; or the
// variances options.pose_mean_variance gives, one per pose and axis (e.g. from the Allan
// variance of the log at the pose's duration, estimation/statistics/allan_variance.h), which the
// noise model of the pose means then is. options.quantisation_variance is added to either, per
// axis: the error of a quantised output's pose mean that does not average down
// (estimation/triad/triad_pose_noise.h).
//
// Refusals (a Status naming what cannot be determined, not a crash): fewer poses than
// parameters + 1; a Jacobian that is rank-deficient at the initial guess or at the solution
// (e.g. all gravity directions in a plane; decided on the reduced information,
// triad_identifiability.h), with the parameters in its null space named and the poses to add
// computed (below); the reduced information not positive definite.
//
// The poses to add: each pose p gives the parameters the rank-one information a_p a_p^T
// (its direction marginalised: a_p = J_p^T q_p, q_p the residual direction the pose's own
// two direction unknowns cannot absorb). Normalised so that its diagonal counts "poses'
// worth" (divided by the mean diagonal of poses spread over the whole sphere), the
// information of the poses held is raised greedily: each step adds, from ~600 directions
// over the sphere (the 26 axis, edge and corner directions preferred on a near tie), the
// one that most increases sum_i log(lambda_i + 1e-3), until the smallest eigenvalue reaches
// that of one sphere-spread pose and there are parameters + 1 poses (at most 12 added).

#include <array>
#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/solver/ceres_solve.h"
#include "estimation/solver/solver_report.h"
#include "estimation/triad/static_intervals.h"
#include "models/triad.h"
#include "models/triad_effect_list.h"

namespace accelcal {

struct TriadMlOptions {
  double gravity_mps2 = 9.81;
  TriadParameters initial = TriadParametersWithOffset(0.0, 0.0, 0.0);  // e.g. imu_tk's solution
  QuietSolveOptions solve;  // LM, tolerances 1e-14 (estimation/solver/ceres_solve.h)
  // A singular value of the column-normalised Jacobian (the directions eliminated:
  // triad_identifiability.h) below this times the largest marks a
  // direction of parameter space the poses do not determine. Exact degeneracy is blurred by
  // noise (directions in a plane give ~1e-6 with 3 counts of noise); well-spread poses give
  // ~0.1.
  double rank_tolerance = 1e-4;
  // Estimate the second-order scale terms k2_k (scale_nonlinearity_x/y/z, 1/(m/s^2)) too.
  bool scale_nonlinearity = false;
  // More coefficients of models/triad_effect_list.h to estimate (indices into
  // TriadEffectCoefficientList()), starting from initial_effects.
  std::vector<int> effects;
  TriadEffectCoefficients initial_effects{};
  // Empty: white noise, s_k^2 / N_p. Otherwise the variance of each pose's mean per axis (the
  // log's unit squared), one entry per pose.
  std::vector<std::array<double, 3>> pose_mean_variance;
  // Added to every pose mean's variance, per axis (the log's unit squared): the rounding of a
  // quantised output (QuantisationBiasVariance); 0 adds nothing.
  std::array<double, 3> quantisation_variance{};
  // On a refusal, compute the poses to add (a search over ~600 directions; discovery, which
  // fits effects it knows to be unidentifiable, does not need them).
  bool suggest_poses = true;
};

// The effect coefficients estimated (indices into TriadEffectCoefficientList(), ascending).
std::vector<int> TriadEstimatedEffects(const TriadMlOptions& options);

// 9 plus the effect coefficients estimated.
int TriadEstimatedParameterCount(const TriadMlOptions& options);

using TriadCovariance = std::array<std::array<double, kTriadParameterCount>, kTriadParameterCount>;

struct TriadMlResult {
  TriadParameters parameters{};
  TriadParameters stddev{};
  TriadCovariance covariance{};
  std::vector<std::array<double, 3>> directions;          // n_p, unit vectors
  std::vector<std::array<double, 3>> whitened_residuals;  // r_p per pose (dimensionless)
  std::array<double, 3> noise_variance{};                 // pooled s_k^2, counts^2
  std::vector<std::array<double, 3>> mean_stddev;         // sigma_p,k the residuals divide by
  bool mean_stddev_from_caller = false;                   // options.pose_mean_variance given
  int pose_count = 0;
  double chi2 = 0.0;
  int degrees_of_freedom = 0;
  double chi2_per_dof = 0.0;
  double chi2_per_dof_spread = 0.0;  // sqrt(2 / dof)
  double p_value = 0.0;              // P(chi2_dof > chi2)
  SolverReport solver;

  // The effect coefficients estimated (TriadEstimatedEffects), their values, sigmas and
  // covariance blocks (covariance above stays the 9 parameters' block); zero for the others.
  // time_origin_s: the time offset_drift_k is referred to (s, the log's clock).
  std::vector<int> effects_estimated;
  TriadEffectCoefficients effects{};
  TriadEffectCoefficients effects_stddev{};
  std::array<TriadEffectCoefficients, kTriadEffectCoefficientCount> effects_covariance{};
  // [i][c]: covariance of triad parameter i with coefficient c.
  std::array<TriadEffectCoefficients, kTriadParameterCount> cross_covariance{};
  double time_origin_s = 0.0;

  // When refused because the poses cannot determine the model: the parameters in the null
  // space, and the poses to add, as unit specific-force directions in the sensor frame (the
  // direction that points up when the sensor is held still), best first.
  std::vector<std::string> unidentifiable;
  std::vector<std::array<double, 3>> suggested_directions;
};

// Fails, naming what the poses cannot determine, as stated above. The poses' variances must
// be positive (a pose of one sample or a constant output cannot give its noise).
Status CalibrateTriadMl(const std::vector<TriadPoseMean>& poses, const TriadMlOptions& options,
                        TriadMlResult* result);

// The noise model's variance per axis, pooled over the poses (each of at least 2 samples; the
// callers check, each saying which of its poses is short):
//   s_k^2 = sum_p (N_p - 1) s_p,k^2 / sum_p (N_p - 1).
// Zero or not finite when no pose varies on an axis; the callers refuse that in their words.
std::array<double, 3> PooledWithinPoseVariance(const std::vector<TriadPoseMean>& poses);

// The pose of each interval of at least `min_samples` samples: mean and sample variance of all
// its samples.
std::vector<TriadPoseMean> PoseMeansOfIntervals(const TriadLog& log,
                                                const std::vector<StaticInterval>& intervals,
                                                int min_samples);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_ML_CALIBRATION_H_
