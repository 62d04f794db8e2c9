#include "estimation/linear_ls.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/format.h"
#include "estimation/chi_square.h"
#include "models/tilt_table.h"

namespace accelcal {

void AxisRegressionAccumulator::Add(double specific_force, double response) {
  if (count_ == 0) {
    shift_force_ = specific_force;
    shift_response_ = response;
  }
  const double f = specific_force - shift_force_;
  const double y = response - shift_response_;
  ++count_;
  sum_force_ += f;
  sum_response_ += y;
  sum_force_force_ += f * f;
  sum_force_response_ += f * y;
  sum_response_response_ += y * y;
}

void AxisRegressionAccumulator::Merge(const AxisRegressionAccumulator& other) {
  if (other.count_ == 0) return;
  if (count_ == 0) {
    *this = other;
    return;
  }
  // Re-express the other's sums about this accumulator's shift: with
  // f' = f_other + df (df the difference of shifts), sum f'^2 = sum f^2 + 2 df sum f + n df^2.
  const double df = other.shift_force_ - shift_force_;
  const double dy = other.shift_response_ - shift_response_;
  const double n = static_cast<double>(other.count_);
  sum_force_force_ += other.sum_force_force_ + 2.0 * df * other.sum_force_ + n * df * df;
  sum_response_response_ +=
      other.sum_response_response_ + 2.0 * dy * other.sum_response_ + n * dy * dy;
  sum_force_response_ +=
      other.sum_force_response_ + dy * other.sum_force_ + df * other.sum_response_ + n * df * dy;
  sum_force_ += other.sum_force_ + n * df;
  sum_response_ += other.sum_response_ + n * dy;
  count_ += other.count_;
}

double AxisRegressionAccumulator::CenteredForceForce() const {
  return std::max(0.0, sum_force_force_ - sum_force_ * sum_force_ / count_);
}

double AxisRegressionAccumulator::CenteredForceResponse() const {
  return sum_force_response_ - sum_force_ * sum_response_ / count_;
}

double AxisRegressionAccumulator::CenteredResponseResponse() const {
  return std::max(0.0, sum_response_response_ - sum_response_ * sum_response_ / count_);
}

void CalibrationAccumulator::Add(double theta_rad, double measured_x, double measured_y) {
  double force_x;
  double force_y;
  TiltTableSpecificForce(theta_rad, 0.0, gravity_mps2_, &force_x, &force_y);
  // The baseline has no non-orthogonality: each axis senses its own component.
  x_.Add(force_x, measured_x - force_x);
  y_.Add(force_y, measured_y - force_y);
  if (x_.count() == 1) theta_min_rad_ = theta_max_rad_ = theta_rad;
  theta_min_rad_ = std::min(theta_min_rad_, theta_rad);
  theta_max_rad_ = std::max(theta_max_rad_, theta_rad);
}

void CalibrationAccumulator::AddTest(const CalibrationTest& test) {
  for (int i = 0; i < test.size(); ++i)
    Add(test.theta_rad[i], test.measured_x[i], test.measured_y[i]);
}

namespace {

// Solves one axis into the rows/columns `first` (bias) and `first + 1` (scale).
Status SolveAxis(const AxisRegressionAccumulator& axis, const char* axis_name,
                 double noise_variance, const CalibrationAccumulator& statistics,
                 double max_variance_inflation, BaselineFit* fit, int first, AxisChiSquare* chi2) {
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
  const double bias = axis.MeanResponse() - scale * mean_force;
  const double residual_sum_squares =
      std::max(0.0, axis.CenteredResponseResponse() - scale * axis.CenteredForceResponse());
  fit->parameters[first] = bias;
  fit->parameters[first + 1] = scale;
  // sigma^2 (A^T A)^-1 written with centred sums, which stay accurate when mean_f is large.
  fit->covariance(first, first) =
      noise_variance * (1.0 / n + mean_force * mean_force / centered_ff);
  fit->covariance(first, first + 1) = -noise_variance * mean_force / centered_ff;
  fit->covariance(first + 1, first) = fit->covariance(first, first + 1);
  fit->covariance(first + 1, first + 1) = noise_variance / centered_ff;
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
                                     options.max_variance_inflation, &result, kBiasX,
                                     &result.chi2_x));
  ACCELCAL_RETURN_IF_ERROR(SolveAxis(statistics.y(), "y", options.noise_variance_y, statistics,
                                     options.max_variance_inflation, &result, kBiasY,
                                     &result.chi2_y));
  *fit = result;
  return Status::Ok();
}

Status EstimateLinearLs(const CalibrationTest& test, const LinearLsOptions& options,
                        BaselineFit* fit) {
  CalibrationAccumulator statistics(options.gravity_mps2);
  statistics.AddTest(test);
  return SolveLinearLs(statistics, options, fit);
}

}  // namespace accelcal
