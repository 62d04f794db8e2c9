#include "estimation/tilt_table/error_budget.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace accelcal {
namespace {

// d endpoint[axis] / d parameter: the trajectory's Jacobian column of `parameter`.
double Derivative(const DeadReckoningResult& trajectory, int axis, Parameter parameter) {
  const std::vector<Parameter>& columns = trajectory.jacobian_columns;
  const auto column = std::find(columns.begin(), columns.end(), parameter);
  assert(column != columns.end() && "the trajectory was not dead-reckoned with this parameter");
  return trajectory.jacobian(axis, static_cast<int>(column - columns.begin()));
}

}  // namespace

std::array<AxisErrorBudget, 2> ComputeErrorBudget(const DeadReckoningResult& trajectory,
                                                  const BaselineFit& fit, const VehicleRun& run,
                                                  const RunConditions& conditions) {
  std::array<AxisErrorBudget, 2> budgets;
  const double t_f = trajectory.duration_s;
  for (int k = 0; k < 2; ++k) {
    AxisErrorBudget& budget = budgets[k];
    budget.axis = k == 0 ? "x" : "y";
    const Parameter bias = BiasOf(k);
    const Parameter scale = ScaleOf(k);
    const std::vector<double>& measured = k == 0 ? run.measured_x : run.measured_y;
    double a_max = 0.0;
    for (double a : measured) a_max = std::max(a_max, std::abs(a));
    const double sigma_b = fit.StandardDeviation(bias);
    const double sigma_s = fit.StandardDeviation(scale);
    const double sigma_eta =
        std::sqrt(k == 0 ? conditions.noise_variance_x : conditions.noise_variance_y);

    budget.bias.report_m = 0.5 * t_f * t_f * 3.0 * sigma_b;
    budget.scale.report_m = 0.5 * t_f * t_f * 3.0 * a_max * sigma_s;
    budget.noise.report_m = 3.0 * sigma_eta;
    budget.report_bound_m = budget.bias.report_m + budget.scale.report_m + budget.noise.report_m;

    const double bias_variance = std::pow(Derivative(trajectory, k, bias) * sigma_b, 2);
    const double scale_variance = std::pow(Derivative(trajectory, k, scale) * sigma_s, 2);
    const double noise_variance = trajectory.noise_part(k, k);
    const double total_variance = trajectory.covariance(k, k);
    budget.bias.three_sigma_m = 3.0 * std::sqrt(bias_variance);
    budget.scale.three_sigma_m = 3.0 * std::sqrt(scale_variance);
    budget.noise.three_sigma_m = 3.0 * std::sqrt(noise_variance);
    budget.three_sigma_m = 3.0 * std::sqrt(total_variance);
    budget.bias.variance_share = bias_variance / total_variance;
    budget.scale.variance_share = scale_variance / total_variance;
    budget.noise.variance_share = noise_variance / total_variance;
    budget.dominant = "noise";
    if (bias_variance > std::max(scale_variance, noise_variance)) budget.dominant = "bias";
    if (scale_variance > std::max(bias_variance, noise_variance)) budget.dominant = "scale";
  }
  return budgets;
}

}  // namespace accelcal
