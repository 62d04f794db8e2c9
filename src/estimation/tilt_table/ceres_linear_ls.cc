#include "estimation/tilt_table/ceres_linear_ls.h"

#include <ceres/ceres.h>

#include <array>
#include <cmath>
#include <vector>

#include "estimation/solver/ceres_solve.h"
#include "estimation/statistics/chi_square.h"
#include "residuals/baseline_calibration_residual.h"

namespace accelcal {

Status EstimateLinearLsWithCeres(const CalibrationTest& test, const CeresLinearLsOptions& options,
                                 CeresLinearLsResult* result) {
  // The closed form's validation (variances, g, sample count, separability) applies
  // unchanged; running it first gives both solvers the same message for the same input,
  // and its solution is a free, exact starting point we deliberately do not use: Ceres
  // starts from zero so that the comparison tests the solver, not the initial guess.
  BaselineFit closed_form;
  ACCELCAL_RETURN_IF_ERROR(EstimateLinearLs(test, options.model, &closed_form));

  std::array<double, kBaselineParameterCount> parameters = {0.0, 0.0, 0.0, 0.0};
  double* bias_x = &parameters[BaselineIndex(Parameter::kBiasX)];
  double* scale_x = &parameters[BaselineIndex(Parameter::kScaleX)];
  double* bias_y = &parameters[BaselineIndex(Parameter::kBiasY)];
  double* scale_y = &parameters[BaselineIndex(Parameter::kScaleY)];

  ceres::Problem problem;
  const double sigma_x = std::sqrt(options.model.noise_variance_x);
  const double sigma_y = std::sqrt(options.model.noise_variance_y);
  std::vector<ceres::ResidualBlockId> x_blocks;
  std::vector<ceres::ResidualBlockId> y_blocks;
  x_blocks.reserve(test.size());
  y_blocks.reserve(test.size());
  for (int i = 0; i < test.size(); ++i) {
    x_blocks.push_back(problem.AddResidualBlock(
        BaselineCalibrationResidual::Create(test.theta_rad[i], test.measured_x[i], SensingAxis::kX,
                                            options.model.gravity_mps2, sigma_x),
        nullptr, bias_x, scale_x));
    y_blocks.push_back(problem.AddResidualBlock(
        BaselineCalibrationResidual::Create(test.theta_rad[i], test.measured_y[i], SensingAxis::kY,
                                            options.model.gravity_mps2, sigma_y),
        nullptr, bias_y, scale_y));
  }

  // The problem is linear: Levenberg-Marquardt with a large initial trust region takes a
  // Gauss-Newton step at once and then only confirms it; the tolerances are tight so
  // the comparison with the closed form is limited by rounding, not by stopping early.
  QuietSolveOptions solve;
  solve.max_iterations = options.max_iterations;
  solve.num_threads = options.num_threads;
  solve.tolerance = 1e-15;
  solve.initial_trust_region_radius = 1e12;
  ACCELCAL_RETURN_IF_ERROR(SolveQuietly(solve, &problem, &result->solver));

  ceres::Covariance::Options covariance_options;
  covariance_options.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance covariance(covariance_options);
  // One block per baseline parameter, in BaselineFit's order.
  std::array<const double*, kBaselineParameterCount> blocks;
  for (const Parameter parameter : kBaselineParameters) {
    blocks[BaselineIndex(parameter)] = &parameters[BaselineIndex(parameter)];
  }
  std::vector<std::pair<const double*, const double*>> pairs;
  for (int a = 0; a < kBaselineParameterCount; ++a) {
    for (int b = a; b < kBaselineParameterCount; ++b) pairs.emplace_back(blocks[a], blocks[b]);
  }
  if (!covariance.Compute(pairs, &problem)) {
    return Status::Error(
        "ceres::Covariance could not compute the parameter covariance "
        "(the Jacobian is rank deficient at the solution)");
  }
  BaselineFit& fit = result->fit;
  fit.sample_count = test.size();
  for (int a = 0; a < kBaselineParameterCount; ++a) {
    fit.parameters[a] = *blocks[a];
    for (int b = a; b < kBaselineParameterCount; ++b) {
      double value;
      covariance.GetCovarianceBlock(blocks[a], blocks[b], &value);
      fit.covariance(a, b) = fit.covariance(b, a) = value;
    }
  }

  // Chi-square per axis: evaluate the whitened residuals of each axis's blocks.
  auto axis_chi_square = [&](const std::vector<ceres::ResidualBlockId>& axis_blocks) {
    ceres::Problem::EvaluateOptions evaluate_options;
    evaluate_options.residual_blocks = axis_blocks;
    double cost = 0.0;
    problem.Evaluate(evaluate_options, &cost, nullptr, nullptr, nullptr);
    AxisChiSquare chi2;
    chi2.chi2 = 2.0 * cost;
    chi2.dof = static_cast<int>(axis_blocks.size()) - 2;
    chi2.p_value = ChiSquareTwoSidedPValue(chi2.chi2, chi2.dof);
    return chi2;
  };
  fit.chi2_x = axis_chi_square(x_blocks);
  fit.chi2_y = axis_chi_square(y_blocks);
  return Status::Ok();
}

}  // namespace accelcal
