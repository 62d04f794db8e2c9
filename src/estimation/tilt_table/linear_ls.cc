#include "estimation/tilt_table/linear_ls.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/format.h"
#include "estimation/statistics/chi_square.h"

namespace accelcal {

namespace {

// What a tilt test must determine for its fit to be an answer: each scale to 10%, and each
// scale error within 50% (beyond it the outputs are in another unit, or g is wrong).
constexpr double kMaxScaleStddev = 0.1;
constexpr double kMaxScaleError = 0.5;

// Solves axis `axis_index` (0: x, 1: y) into its bias's and scale's places of the fit.
Status SolveAxis(const AxisRegressionAccumulator& axis, const char* axis_name,
                 double noise_variance, const CalibrationAccumulator& statistics,
                 double max_variance_inflation, BaselineFit* fit, int axis_index,
                 AxisChiSquare* chi2) {
  const int b = BaselineIndex(BiasOf(axis_index));
  const int s = BaselineIndex(ScaleOf(axis_index));
  const double n = static_cast<double>(axis.count());
  const double centered_ff = axis.CenteredForceForce();
  const double mean_force = axis.MeanForce();
  // Variance inflation of the bias by its correlation with the scale:
  // 1 / (1 - rho^2) = 1 + mean_f^2 / var_f.
  const double variance_inflation =
      centered_ff > 0.0 ? 1.0 + mean_force * mean_force * n / centered_ff : HUGE_VAL;
  if (!(variance_inflation <= max_variance_inflation)) {
    const double span = statistics.theta_max_rad() - statistics.theta_min_rad();
    const double force_spread = std::sqrt(centered_ff / n);
    return Status::Error("theta spans " + StringPrintf("%.3g", span) + " rad: bias_" + axis_name +
                         " and scale_" + axis_name + " cannot be separated (the " + axis_name +
                         " axis' specific force varies by " + StringPrintf("%.2g", force_spread) +
                         " m/s^2 rms about " + StringPrintf("%.3g", mean_force) +
                         " m/s^2, so the two estimates would be " +
                         StringPrintf("%.7f", std::sqrt(1.0 - 1.0 / variance_inflation)) +
                         " correlated); rotate the table through a wider range of angles");
  }
  // The test must exercise the axis: with its force nearly constant (a test at theta 0 and pi
  // leaves f_x = -g sin(theta) at 0 throughout) the bias is fine but the scale is whatever
  // the noise makes it (1.7e13 was reported, exit 0). Refused when the scale could not be
  // known to 10%.
  const double scale_stddev = std::sqrt(noise_variance / centered_ff);
  if (!(scale_stddev <= kMaxScaleStddev)) {
    return Status::Error(StringPrintf(
        "the %s axis' specific force varies by only %.2g m/s^2 rms over the test (theta from "
        "%.4g to %.4g rad), so scale_%s could not be known better than +-%.2g: the positions do "
        "not exercise the %s axis; add positions where %s differs (f_x = -g sin(theta), "
        "f_y = -g cos(theta))",
        axis_name, std::sqrt(centered_ff / n), statistics.theta_min_rad(),
        statistics.theta_max_rad(), axis_name, scale_stddev, axis_name,
        axis_name[0] == 'x' ? "sin(theta)" : "cos(theta)"));
  }
  const double scale = axis.CenteredForceResponse() / centered_ff;
  if (!(1.0 + scale > 0.0)) {
    // The output falls as the model's specific force rises: an inverted axis, theta turning
    // the other way, or swapped axes. No scale factor *error* explains that, and the run
    // could not be corrected with it, so say what the model expects instead.
    return Status::Error(StringPrintf(
        "the tilt test gives scale_%s = %.4g (1 + scale_%s <= 0): the %s output falls as the "
        "model's specific force rises; check the axis' sign, the order x then y, and that theta "
        "follows the spec (f_x = -g sin(theta), f_y = -g cos(theta))",
        axis_name, scale, axis_name, axis_name));
  }
  if (std::abs(scale) > kMaxScaleError) {
    // No scale factor error is 50%: outputs in g or mg, or a wrong g, read as one.
    const double ratio = 1.0 + scale;
    const char* hint = ratio < 0.2    ? "are the outputs in g rather than m/s^2?"
                       : ratio > 50.0 ? "are the outputs in mg or cm/s^2 rather than m/s^2?"
                                      : "are the outputs in m/s^2, and is g (--g, or gravity "
                                        "in scenario.json) right?";
    return Status::Error(StringPrintf(
        "the tilt test gives scale_%s = %.4g: the %s output is %.3g times what g = %.6g m/s^2 "
        "predicts, which no scale factor error explains; %s",
        axis_name, scale, axis_name, ratio, statistics.gravity_mps2(), hint));
  }
  const double bias = axis.MeanResponse() - scale * mean_force;
  const double residual_sum_squares =
      std::max(0.0, axis.CenteredResponseResponse() - scale * axis.CenteredForceResponse());
  fit->parameters[b] = bias;
  fit->parameters[s] = scale;
  // sigma^2 (A^T A)^-1 written with centred sums, which stay accurate when mean_f is large.
  fit->covariance(b, b) = noise_variance * (1.0 / n + mean_force * mean_force / centered_ff);
  fit->covariance(b, s) = -noise_variance * mean_force / centered_ff;
  fit->covariance(s, b) = fit->covariance(b, s);
  fit->covariance(s, s) = noise_variance / centered_ff;
  chi2->chi2 = residual_sum_squares / noise_variance;
  chi2->dof = static_cast<int>(axis.count()) - 2;
  chi2->p_value = ChiSquareTwoSidedPValue(chi2->chi2, chi2->dof);
  return Status::Ok();
}

Status CheckPositive(double value, const char* name, const char* unit) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    return Status::Error(std::string(name) + " must be a positive finite number in " + unit +
                         ", got " + StringPrintf("%g", value));
  }
  return Status::Ok();
}

}  // namespace

Status SolveLinearLs(const CalibrationAccumulator& statistics, const LinearLsOptions& options,
                     BaselineFit* fit) {
  ACCELCAL_RETURN_IF_ERROR(
      CheckPositive(options.noise_variance_x, "noise_variance_x", "(m/s^2)^2"));
  ACCELCAL_RETURN_IF_ERROR(
      CheckPositive(options.noise_variance_y, "noise_variance_y", "(m/s^2)^2"));
  ACCELCAL_RETURN_IF_ERROR(CheckPositive(options.gravity_mps2, "g", "m/s^2"));
  if (statistics.x().count() < 3) {
    return Status::Error("the tilt test has " + std::to_string(statistics.x().count()) +
                         " sample(s); at least 3 are needed to estimate bias and scale and "
                         "check the fit");
  }
  BaselineFit result;
  result.sample_count = static_cast<int>(statistics.x().count());
  ACCELCAL_RETURN_IF_ERROR(SolveAxis(statistics.x(), "x", options.noise_variance_x, statistics,
                                     options.max_variance_inflation, &result, 0, &result.chi2_x));
  ACCELCAL_RETURN_IF_ERROR(SolveAxis(statistics.y(), "y", options.noise_variance_y, statistics,
                                     options.max_variance_inflation, &result, 1, &result.chi2_y));
  *fit = result;
  return Status::Ok();
}

Status EstimateLinearLs(const CalibrationTest& test, const LinearLsOptions& options,
                        BaselineFit* fit) {
  CalibrationAccumulator statistics(options.gravity_mps2);
  statistics.AddTest(test);
  return SolveLinearLs(statistics, options, fit);
}

Status EstimateLinearLsWithNoiseFromResiduals(const CalibrationTest& test, LinearLsOptions* options,
                                              BaselineFit* fit) {
  options->noise_variance_x = options->noise_variance_y = 1.0;
  ACCELCAL_RETURN_IF_ERROR(EstimateLinearLs(test, *options, fit));
  options->noise_variance_x = fit->chi2_x.chi2 / fit->chi2_x.dof;
  options->noise_variance_y = fit->chi2_y.chi2 / fit->chi2_y.dof;
  return EstimateLinearLs(test, *options, fit);
}

}  // namespace accelcal
