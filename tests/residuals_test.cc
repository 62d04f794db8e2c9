// Every residual: zero at the truth, whitened by the stated noise, its value equal to the
// spec's model written out independently here in plain double arithmetic (not through
// models/, which the residuals themselves call, so a wrong sign or a dropped term in the
// model cannot hide by appearing on both sides), and its Jacobian equal to central
// differences of that independent model and to ceres::GradientChecker.

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "models/sensor_model.h"
#include "residuals/baseline_calibration_residual.h"
#include "residuals/calibration_residual.h"
#include "test_support.h"

namespace accelcal {
namespace {

constexpr double kG = 9.8;

// ../shared/spec/error-model.md, "Frames and the tilt-table test" and "Sensor output", for
// one tilt-test sample, written out term by term. `p` holds the spec's symbols by name.
struct SpecParameters {
  double bias_x = 0.0, scale_x = 0.0, bias_y = 0.0, scale_y = 0.0;
  double angle_offset = 0.0;                                      // delta
  double nonorthogonality = 0.0;                                  // eps
  double bias_drift_x = 0.0, bias_drift_y = 0.0;                  // d_k
  double scale_nonlinearity_x = 0.0, scale_nonlinearity_y = 0.0;  // k2_k
};

double SpecOutput(double theta_reported, double u, SensingAxis axis, const SpecParameters& p) {
  const double theta_true = theta_reported + p.angle_offset;
  const double fx = -kG * std::sin(theta_true);
  const double fy = -kG * std::cos(theta_true);
  if (axis == SensingAxis::kX) {
    const double f = fx;
    return (1.0 + p.scale_x) * f + p.scale_nonlinearity_x * f * f + p.bias_x + p.bias_drift_x * u;
  }
  const double f = fy * std::cos(p.nonorthogonality) + fx * std::sin(p.nonorthogonality);
  return (1.0 + p.scale_y) * f + p.scale_nonlinearity_y * f * f + p.bias_y + p.bias_drift_y * u;
}

// The spec's parameter behind each of the library's parameters of the tilt test.
double* SpecField(Parameter parameter, SpecParameters* p) {
  const std::map<std::string, double*> by_name = {
      {"bias_x", &p->bias_x},
      {"scale_x", &p->scale_x},
      {"bias_y", &p->bias_y},
      {"scale_y", &p->scale_y},
      {"angle_offset", &p->angle_offset},
      {"nonorthogonality", &p->nonorthogonality},
      {"bias_drift_x", &p->bias_drift_x},
      {"bias_drift_y", &p->bias_drift_y},
      {"scale_nonlinearity_x", &p->scale_nonlinearity_x},
      {"scale_nonlinearity_y", &p->scale_nonlinearity_y}};
  const auto found = by_name.find(Info(parameter).name);
  return found == by_name.end() ? nullptr : found->second;
}

// Parameters far from neutral (every term visible), as the spec's values and the library's.
SpecParameters SomeSpecParameters() {
  SpecParameters p;
  p.bias_x = 0.07;
  p.scale_x = -0.03;
  p.bias_y = -0.02;
  p.scale_y = 0.01;
  p.angle_offset = 0.02;
  p.nonorthogonality = -0.015;
  p.bias_drift_x = 0.05;
  p.bias_drift_y = -0.08;
  p.scale_nonlinearity_x = 0.002;
  p.scale_nonlinearity_y = -0.003;
  return p;
}

ModelParameters<double> LibraryParameters(const SpecParameters& spec) {
  ModelParameters<double> values;
  SpecParameters copy = spec;
  for (int i = 0; i < kParameterCount; ++i) {
    const double* field = SpecField(Parameter(i), &copy);
    if (field != nullptr) values[Parameter(i)] = *field;
  }
  return values;
}

TEST(BaselineCalibrationResidual, IsZeroAtTrueParameters) {
  SpecParameters truth;
  truth.bias_x = truth.bias_y = 0.05;
  truth.scale_x = truth.scale_y = -0.02;
  for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
    for (const double theta : {0.0, 0.4, 2.0, 4.5}) {
      const double measured = SpecOutput(theta, 0.0, axis, truth);
      const std::unique_ptr<ceres::CostFunction> cost(
          BaselineCalibrationResidual::Create(theta, measured, axis, kG, 0.5));
      const double bias = 0.05;
      const double scale = -0.02;
      const double* parameters[] = {&bias, &scale};
      double residual = 1.0;
      ASSERT_TRUE(cost->Evaluate(parameters, &residual, nullptr));
      EXPECT_NEAR(residual, 0.0, 1e-14);
    }
  }
}

// Away from the truth: r = (m - (1 + s) f - b) / sigma, with f = -g sin(theta) for x and
// -g cos(theta) for y, and its exact derivatives -1/sigma and -f/sigma.
TEST(BaselineCalibrationResidual, IsTheSpecsWhitenedErrorWithItsExactJacobian) {
  const double sigma = 0.8;
  for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
    for (const double theta : {0.3, 1.9, 3.7, 5.5}) {
      const double force = axis == SensingAxis::kX ? -kG * std::sin(theta) : -kG * std::cos(theta);
      const double measured = 1.234 - 0.5 * force;
      const std::unique_ptr<ceres::CostFunction> cost(
          BaselineCalibrationResidual::Create(theta, measured, axis, kG, sigma));
      const double bias = 0.07;
      const double scale = 0.01;
      const double* parameters[] = {&bias, &scale};
      double residual = 0.0;
      double d_bias = 0.0;
      double d_scale = 0.0;
      double* jacobians[] = {&d_bias, &d_scale};
      ASSERT_TRUE(cost->Evaluate(parameters, &residual, jacobians));
      EXPECT_NEAR(residual, (measured - (1.0 + scale) * force - bias) / sigma, 1e-13);
      EXPECT_NEAR(d_bias, -1.0 / sigma, 1e-15);
      EXPECT_NEAR(d_scale, -force / sigma, 1e-13);
    }
  }
}

TEST(BaselineCalibrationResidual, IsWhitenedByTheStatedNoise) {
  const double measured = -kG * std::sin(1.0) + 0.3;
  const std::unique_ptr<ceres::CostFunction> cost(
      BaselineCalibrationResidual::Create(1.0, measured, SensingAxis::kX, kG, 0.5));
  const double zero = 0.0;
  const double* parameters[] = {&zero, &zero};
  double residual;
  ASSERT_TRUE(cost->Evaluate(parameters, &residual, nullptr));
  EXPECT_NEAR(residual, 0.3 / 0.5, 1e-14);
}

TEST(BaselineCalibrationResidual, GradientCheckerAgreesWithAutodiff) {
  for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
    const std::unique_ptr<ceres::CostFunction> cost(
        BaselineCalibrationResidual::Create(0.9, 1.234, axis, kG, 0.8));
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

// Every tilt-test block of the full model is one the spec names: nothing of the residual
// escapes the independent model below.
TEST(CalibrationResidual, EveryBlockIsAParameterOfTheSpec) {
  SpecParameters p;
  for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
    for (const Parameter parameter : CalibrationResidual::Blocks(axis)) {
      EXPECT_NE(SpecField(parameter, &p), nullptr) << Info(parameter).name;
    }
  }
}

// The full model's residual, far from neutral in every parameter, at several angles and
// drift coordinates, equals (m - SpecOutput) / sigma; its Jacobian equals central differences
// of SpecOutput (step 1e-6 in each parameter: truncation error ~ f''' h^2 ~ 1e-10, rounding
// ~ 1e-16 / 1e-6 ~ 1e-10, so 1e-7 is far above both and far below any term's derivative).
TEST(CalibrationResidual, IsTheSpecsModelWithCentralDifferenceJacobian) {
  const SpecParameters spec = SomeSpecParameters();
  const ModelParameters<double> values = LibraryParameters(spec);
  const double sigma = 0.5;
  for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
    const auto& blocks = CalibrationResidual::Blocks(axis);
    for (const double theta : {0.2, 1.3, 2.9, 4.1, 5.8}) {
      for (const double u : {-0.5, -0.1, 0.35}) {
        SCOPED_TRACE(::testing::Message()
                     << (axis == SensingAxis::kX ? "x" : "y") << " theta " << theta << " u " << u);
        const double measured = 0.9 - 0.7 * std::cos(theta + 0.4);  // anything
        const std::unique_ptr<ceres::CostFunction> cost(
            CalibrationResidual::Create(theta, measured, axis, u, kG, sigma));
        const std::vector<const double*> pointers = testing::BlockPointers(blocks, values);
        double residual = 0.0;
        std::vector<double> jacobian(blocks.size(), 0.0);
        std::vector<double*> jacobian_rows;
        for (double& entry : jacobian) jacobian_rows.push_back(&entry);
        ASSERT_TRUE(cost->Evaluate(pointers.data(), &residual, jacobian_rows.data()));
        EXPECT_NEAR(residual, (measured - SpecOutput(theta, u, axis, spec)) / sigma, 1e-12);
        for (size_t k = 0; k < blocks.size(); ++k) {
          const double step = 1e-6;
          SpecParameters plus = spec;
          SpecParameters minus = spec;
          *SpecField(blocks[k], &plus) += step;
          *SpecField(blocks[k], &minus) -= step;
          const double derivative =
              -(SpecOutput(theta, u, axis, plus) - SpecOutput(theta, u, axis, minus)) /
              (2 * step * sigma);
          EXPECT_NEAR(jacobian[k], derivative, 1e-7) << Info(blocks[k]).name;
        }
      }
    }
  }
}

// With time-correlated noise the residual is current e_i - previous e_{i-1}, each e the
// spec's error of its own sample (its own angle and drift coordinate).
TEST(CalibrationResidual, WhitenedFormDifferencesTheSpecsErrorsOfTwoSamples) {
  const SpecParameters spec = SomeSpecParameters();
  const ModelParameters<double> values = LibraryParameters(spec);
  for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
    const CalibrationResidual::Sample current{2.0, -3.1, 0.12};
    const CalibrationResidual::Sample previous{1.99, -3.3, 0.11};
    const std::unique_ptr<ceres::CostFunction> cost(
        CalibrationResidual::CreateWhitened(current, previous, axis, kG, 2.5, 1.5));
    const std::vector<const double*> pointers =
        testing::BlockPointers(CalibrationResidual::Blocks(axis), values);
    double residual = 0.0;
    ASSERT_TRUE(cost->Evaluate(pointers.data(), &residual, nullptr));
    const double e_current =
        current.measured_mps2 - SpecOutput(current.theta_rad, current.drift_coordinate, axis, spec);
    const double e_previous = previous.measured_mps2 -
                              SpecOutput(previous.theta_rad, previous.drift_coordinate, axis, spec);
    EXPECT_NEAR(residual, 2.5 * e_current - 1.5 * e_previous, 1e-12);
  }
}

// u_i of the spec: i/(N-1) - 0.5.
TEST(DriftCoordinate, IsTheSpecsLinearRampWithZeroMean) {
  EXPECT_DOUBLE_EQ(DriftCoordinate(0, 11), -0.5);
  EXPECT_DOUBLE_EQ(DriftCoordinate(10, 11), 0.5);
  EXPECT_DOUBLE_EQ(DriftCoordinate(3, 11), 3.0 / 10.0 - 0.5);
}

}  // namespace
}  // namespace accelcal
