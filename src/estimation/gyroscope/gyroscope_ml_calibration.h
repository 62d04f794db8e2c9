#ifndef ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_ML_CALIBRATION_H_
#define ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_ML_CALIBRATION_H_

// The gyroscope's maximum-likelihood calibration with covariance (issue 32, docs/gyroscope.md),
// from the session the accelerometer's maximum-likelihood calibration
// (estimation/triad/triad_ml_calibration.h) has already fitted: its static poses, and the turns
// between consecutive ones.
//
// One problem, jointly with the accelerometer's poses (not conditioned on its answer): the
// unknowns are the accelerometer's 9 parameters, one unit gravity direction n_p per pose, the
// gyroscope's 9 parameters, its offset b (3) and the effect coefficients estimated
// (models/gyroscope_effect_list.h); the residuals, each whitened,
//   - the accelerometer's pose means (residuals/triad_pose_residual.h, weighted as its own fit
//     weighted them: TriadMlResult::mean_stddev), 3 per pose;
//   - the gyroscope's pose means (GyroscopeRestResidual), 3 per pose: the offset comes from
//     every static pose, not only an initial rest;
//   - one per turn (GyroscopeTurnResidual), 2 each: the rotation the calibrated rates integrate
//     to must carry n_p onto n_p+1.
// The accelerometer's uncertainty is carried into the gyroscope's covariance because the
// directions are unknowns of the same problem; the accelerometer's own reported calibration stays
// its fit alone (the joint fit's accelerometer parameters are compared with it: `accelerometer_
// shift_sigma`).
//
// Noise model, per axis k, from the gyroscope's own samples:
//   - the white noise s_k^2 (the output's unit squared) pooled within the poses, as the
//     accelerometer's (PooledWithinPoseVariance), plus q^2/12 for an output quantised in steps
//     of q (options.quantisation_step);
//   - a pose mean of N samples: s_k^2 / N, plus the Earth's rate (7.292e-5 rad/s, whose
//     direction in the body is not known) as a random rate of variance Omega^2 / 3 per axis when
//     options.earth_rate_as_noise;
//   - a turn: the white noise integrated, the angle's variance gain_k^2 s_k^2 sum_i c_i^2 (rad^2,
//     c_i the trapezoid weights of sample i, s), plus (Omega T)^2 / 3 for the Earth's rate over
//     the turn's T seconds when options.earth_rate_as_noise; the residual's 2 x 2 covariance is
//     that angle covariance seen at n_p+1: E^T [n]x S [n]x^T E.
//   - a bias wander: when the poses' offsets scatter beyond that (bias instability, temperature),
//     a variance tau_k^2 between poses estimated from their scatter when significant
//     (options.bias_wander_alpha) added to every pose mean, and (gain_k tau_k T)^2 to a turn's
//     angle; the fit is repeated with it. The rest residuals then fit by construction; the turns
//     are the check.
//   - what the samples do not resolve (docs/gyroscope.md, "The turns' sampling error"): a turn's
//     rate is sampled, and where it changes abruptly between two samples (a hand that stops the
//     sensor against a table) no integration rule recovers the rotation between them: the
//     integral of the samples misses it by about |delta w| dt times a fraction that depends on
//     when, within the step, the change happened. Each turn's angle gets the variance
//     kappa^2 gain_k^2 D_k per axis, D_k = sum_j (u_k,j+1 - u_k,j)^2 dt_j^2 over the turn's steps
//     less what the white noise puts there (2 s_k^2 sum_j dt_j^2), kappa^2 (dimensionless: 1/12
//     for steps at uniformly random times within a sample interval) estimated when the turns
//     reject the noise model without it (options.turn_sampling_alpha), by the method of moments
//     over the turns, and the fit repeated with it. The turns then fit by construction in
//     total; whether their residuals follow D (and nothing else: rate, angle, axis, duration,
//     time) is discovery's check of the turns' shapes (gyroscope_discovery.h).
//
// Clipping: a turn in which an output sits at the end of its range (the log's largest or smallest
// value on that axis, held for 5 samples or more in a row, as an ADC or a driver saturates) is
// left out of the fit and listed (clipped_turns): its rate was beyond the range, its rotation is
// short.
//
// Refusals: fewer than 2 poses; gyroscope samples missing; a turn of fewer than 2 samples; the
// gyroscope parameters' information (the accelerometer's and the directions' marginalised)
// rank-deficient: the parameters in its near-null space named, with the body axes the turns
// must turn about to determine them (a gain or a misalignment column is determined by turns about
// its axis: GyroscopeTurnAxisOf).

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/solver/ceres_solve.h"
#include "estimation/solver/solver_report.h"
#include "estimation/triad/static_intervals.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "models/gyroscope.h"
#include "models/gyroscope_effect_list.h"
#include "models/gyroscope_units.h"

namespace accelcal {

constexpr double kEarthRateRadPerS = 7.2921159e-5;

// The gyroscope's unknowns in the covariance's order: the 9 parameters, the 3 offsets, then the
// effect coefficients estimated.
constexpr int kGyroscopeOffsetX = kGyroscopeParameterCount;  // index of offset_x in that order
constexpr int kGyroscopeCalibrationCount = kGyroscopeParameterCount + 3;  // 12

struct GyroscopeMlOptions {
  double gravity_mps2 = 9.81;
  GyroscopeOutputUnit unit = GyroscopeOutputUnit::kCount;  // names the units of the results
  GyroscopeParameters initial = GyroscopeParametersWithGain(1.0, 1.0, 1.0);
  // Empty: the offsets start from the mean of the poses' means.
  bool offset_given = false;
  GyroscopeOffset initial_offset{};
  std::vector<int> effects;  // coefficient indices (models/gyroscope_effect_list.h) estimated
  GyroscopeEffectCoefficients initial_effects{};
  double quantisation_step = 0.0;  // the output's step (1 for counts), 0: not quantised
  bool earth_rate_as_noise = true;
  // The Earth's rate at rest is Omega sin(latitude) about the up direction (along the specific
  // force in every pose) and Omega cos(latitude) in the horizontal plane, whose direction in the
  // body is not known. The vertical part is the effect block's earth_rate coefficient
  // (models/gyroscope_effects/earth_rate.h), never among `effects` nor in the result's: with the
  // latitude given, it is held at its value, exactly; the horizontal part is noise of
  // (Omega cos(latitude))^2 / 3 per axis. Without it, the vertical part e moves in the fit with
  // the prior N(0, Omega^2), so that it is modelled where the
  // poses determine it and bounded where they do not, and never taken for a g-sensitivity
  // (G g n_p with G = e/g I is the same pattern); the horizontal part is noise of
  // (Omega^2 - e^2 - var e) / 3 per axis, e from a first fit of the model (or, when
  // `earth_horizontal_fixed`, the given variance: discovery holds the baseline's, so that nested
  // fits share one noise model). Only with earth_rate_as_noise.
  bool latitude_given = false;
  double latitude_rad = 0.0;
  bool earth_horizontal_fixed = false;
  double earth_horizontal_axis_variance = 0.0;  // (rad/s)^2 per axis
  // The bias wander between poses (a variance per axis, the output's unit squared): each pose
  // mean gets it, and each turn the angle of an offset that far off over its duration. When
  // `bias_wander_fixed`, the given one; else it is estimated when the poses' offsets scatter
  // beyond their white noise (the rest residuals' chi-square, white, rejected at
  // bias_wander_alpha; 0: never) by the method of moments, and the fit repeated with it.
  bool bias_wander_fixed = false;
  std::array<double, 3> bias_wander_variance{};
  double bias_wander_alpha = 0.0025;
  // The turns' sampling error kappa^2 (see above): when `turn_sampling_fixed`, the given one;
  // else estimated when the turns' chi-square under the rest of the noise model is rejected at
  // turn_sampling_alpha (0: never).
  bool turn_sampling_fixed = false;
  double turn_sampling_variance = 0.0;
  double turn_sampling_alpha = 0.0;
  // A singular value ratio of the column-normalised marginal information below this marks a
  // direction the turns do not determine.
  double rank_tolerance = 1e-8;
  QuietSolveOptions solve;
};

struct GyroscopeMlTurn {
  int pose_before = 0;
  int first_sample = 0;  // the samples integrated, inclusive (the poses' own end samples)
  int last_sample = 0;
  double duration_s = 0.0;
  double angle_rad = 0.0;           // the angle between n_p and n_p+1 (the tilt turned)
  double rotation_angle_rad = 0.0;  // the whole rotation the calibrated rates integrate to
  double residual_angle_rad = 0.0;  // the angle between R^T n_p and n_p+1 at the solution
  double angle_stddev_rad = 0.0;    // the noise model's per-axis angle sigma over the turn
  // How abruptly the rate changes between the turn's samples: sqrt(sum_k gain_k^2 D_k / 3) (rad,
  // D_k as above), the size of the rotation the samples may miss; the sampling term's angle sigma
  // is kappa times it.
  double sampling_measure_rad = 0.0;
  double peak_rate_rad_s = 0.0;           // the largest calibrated-rate magnitude over the turn
  double time_s = 0.0;                    // the turn's first sample's time, from the log's start
  std::array<double, 3> rotation_axis{};  // the integrated rotation's axis (body, unit)
  std::array<double, 2> whitened{};
};

// A turn left out because the gyroscope's output sat at the end of its range in it: the rate was
// beyond what it measures, so the integrated rotation is short.
struct GyroscopeClippedTurn {
  int pose_before = 0;
  int axis = 0;       // 0: x, 1: y, 2: z
  double rail = 0.0;  // the output it sat at (its unit)
  int samples = 0;    // samples of the turn at the rail
};

struct GyroscopeMlResult {
  GyroscopeParameters parameters{};
  GyroscopeOffset offset{};
  std::vector<int> effects_estimated;
  GyroscopeEffectCoefficients effects{};
  // Over kGyroscopeCalibrationCount + effects_estimated.size() unknowns, in that order.
  Eigen::MatrixXd covariance;
  Eigen::VectorXd stddev;
  std::vector<std::string> names;  // the unknowns' names, in that order
  std::vector<std::string> units;

  std::array<double, 3> noise_variance{};  // the pooled white noise, the output's unit squared
  std::array<double, 3> bias_wander_variance{};  // between poses, the unit squared; 0: none
  double turn_sampling_variance = 0.0;           // kappa^2 of the turns' sampling error; 0: none
  // The Earth's rate along gravity (rad/s): given (latitude_given; stddev 0) or estimated with
  // its prior (see GyroscopeMlOptions); 0 and 0 when the Earth's rate is not counted.
  double earth_vertical_rate_rad_s = 0.0;
  double earth_vertical_rate_stddev = 0.0;
  double earth_vertical_prior_stddev = 0.0;  // the prior's sigma; 0: given or not counted
  // Estimated with the gains, the vertical rate traded with them (they collapsed towards 0, an
  // unmodelled pose-dependent offset's doing): held at its prior's mean instead, stddev 0.
  bool earth_vertical_held = false;
  double earth_horizontal_axis_variance = 0.0;  // the pose means' allowance, (rad/s)^2 per axis
  // The turns' chi-square under the noise model without the sampling term: its p-value.
  double turns_without_sampling_p_value = 1.0;
  double white_rest_p_value = 1.0;  // the rest residuals' chi-square under white noise alone
  std::vector<std::array<double, 3>> rest_means;     // per pose, the output's unit
  std::vector<std::array<double, 3>> rest_whitened;  // per pose
  std::vector<std::array<double, 3>> rest_stddev;    // per pose: the means' sigma
  std::vector<GyroscopeMlTurn> turns;                // the turns fitted
  std::vector<GyroscopeClippedTurn> clipped_turns;   // the turns left out (one entry per turn)
  std::vector<std::array<double, 3>> directions;     // the joint fit's n_p
  // How far the turns went about each body axis (rad): |w_k| integrated over every turn fitted
  // (trapezoid weights, the rates of the fit's gains and offsets at its start), yaws about
  // gravity included. A gain or a misalignment column is determined by turns about its axis
  // (GyroscopeTurnAxisOf); gyroscope_determination.h says how much of the turning each got.
  std::array<double, 3> turned_about_rad{};

  // The fit: every whitened residual of the joint problem (chi2 on degrees_of_freedom); what the
  // gyroscope adds, the joint chi2 minus the accelerometer's fit alone (its residuals nest in the
  // joint problem's), chi-square on the gyroscope's residuals minus its unknowns when both
  // models hold: the gyroscope's fit statistic. chi2_rest and chi2_turns: the sums of the
  // gyroscope's squared whitened residuals by kind, at the joint solution.
  double chi2 = 0.0;
  int degrees_of_freedom = 0;
  double p_value = 1.0;
  double chi2_gyroscope = 0.0;
  int gyroscope_degrees_of_freedom = 0;  // 3 per pose + 2 per turn - the gyroscope's unknowns
  double gyroscope_p_value = 1.0;
  double chi2_turns = 0.0;
  double chi2_rest = 0.0;
  SolverReport solver;

  // The joint fit's accelerometer parameters against the accelerometer's own fit: the largest
  // |difference| / sigma over the 9 (sigma: the accelerometer fit's).
  TriadParameters accelerometer_joint{};
  double accelerometer_shift_sigma = 0.0;

  // The Earth's rate (7.29e-5 rad/s) against the noise, in rad/s: the sigma of one pose's
  // mean (the median over the poses, white noise alone), the offsets' sigma (the largest axis,
  // in rad/s), and per turn the angle sigma against Omega T (the median over the turns).
  double pose_mean_sigma_rad_s = 0.0;
  double offset_sigma_rad_s = 0.0;
  double turn_angle_sigma_rad = 0.0;
  double turn_earth_angle_rad = 0.0;

  // When refused as undetermined: the unknowns named, and the body axes to turn about.
  std::vector<std::string> undetermined;
  std::vector<std::string> turn_axes_to_add;
};

// The axis ("x", "y" or "z") turns must be about to determine gyroscope unknown i (the 9, the 3
// offsets, then effect coefficients), or "" when static poses determine it (the offsets, the
// g-sensitivity).
const char* GyroscopeTurnAxisOf(int unknown, const std::vector<int>& effects_estimated);

// `intervals`: the static intervals of `accelerometer`'s poses, in its order (time order), so
// that pose p is intervals[p]; `accelerometer_options` as its fit ran (g, effects, weights).
Status CalibrateGyroscopeMl(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                            const TriadMlOptions& accelerometer_options,
                            const TriadMlResult& accelerometer, const GyroscopeMlOptions& options,
                            GyroscopeMlResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_ML_CALIBRATION_H_
