// Every residual: zero at the truth, Jacobian agreeing with numeric differentiation
// (ceres::GradientChecker), and whitened by the stated noise.

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <memory>

#include "models/sensor_model.h"
#include "models/tilt_table.h"
#include "residuals/baseline_calibration_residual.h"

namespace accelcal {
namespace {

double NoiselessOutput(double theta, SensingAxis axis, double bias, double scale) {
  double fx;
  double fy;
  TiltTableSpecificForce(theta, 9.8, &fx, &fy);
  return (1.0 + scale) * (axis == SensingAxis::kX ? fx : fy) + bias;
}

TEST(BaselineCalibrationResidual, IsZeroAtTrueParameters) {
  for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
    for (const double theta : {0.0, 0.4, 2.0, 4.5}) {
      const double measured = NoiselessOutput(theta, axis, 0.05, -0.02);
      const std::unique_ptr<ceres::CostFunction> cost(
          BaselineCalibrationResidual::Create(theta, measured, axis, 9.8, 0.5));
      const double bias = 0.05;
      const double scale = -0.02;
      const double* parameters[] = {&bias, &scale};
      double residual = 1.0;
      ASSERT_TRUE(cost->Evaluate(parameters, &residual, nullptr));
      EXPECT_NEAR(residual, 0.0, 1e-14);
    }
  }
}

TEST(BaselineCalibrationResidual, IsWhitenedByTheStatedNoise) {
  const double measured = NoiselessOutput(1.0, SensingAxis::kX, 0.0, 0.0) + 0.3;
  const std::unique_ptr<ceres::CostFunction> cost(
      BaselineCalibrationResidual::Create(1.0, measured, SensingAxis::kX, 9.8, 0.5));
  const double zero = 0.0;
  const double* parameters[] = {&zero, &zero};
  double residual;
  ASSERT_TRUE(cost->Evaluate(parameters, &residual, nullptr));
  EXPECT_NEAR(residual, 0.3 / 0.5, 1e-14);
}

TEST(BaselineCalibrationResidual, GradientCheckerAgreesWithAutodiff) {
  for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
    const std::unique_ptr<ceres::CostFunction> cost(
        BaselineCalibrationResidual::Create(0.9, 1.234, axis, 9.8, 0.8));
    ceres::NumericDiffOptions numeric_options;
    const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
    ceres::GradientChecker checker(cost.get(), no_manifolds, numeric_options);
    const double bias = 0.07;
    const double scale = 0.01;
    const double* parameters[] = {&bias, &scale};
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(parameters, 1e-9, &results)) << results.error_log;
  }
}

}  // namespace
}  // namespace accelcal
