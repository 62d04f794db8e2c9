// The spec's model, term by term (../shared/spec/error-model.md), and its instantiation
// with ceres::Jet so that autodiff breakage shows at compile time.

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "models/dead_reckoning.h"
#include "models/sensor_model.h"
#include "models/tilt_table.h"

namespace accelcal {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(TiltTableSpecificForce, MatchesTheSpecAtTheQuadrants) {
  double fx;
  double fy;
  TiltTableSpecificForce(0.0, 0.0, 9.8, &fx, &fy);
  EXPECT_NEAR(fx, 0.0, 1e-15);
  EXPECT_NEAR(fy, -9.8, 1e-15);
  TiltTableSpecificForce(kPi / 2, 0.0, 9.8, &fx, &fy);
  EXPECT_NEAR(fx, -9.8, 1e-15);
  EXPECT_NEAR(fy, 0.0, 1e-14);
}

TEST(TiltTableSpecificForce, AngleOffsetAddsToTheReportedAngle) {
  double fx_offset;
  double fy_offset;
  double fx_true;
  double fy_true;
  TiltTableSpecificForce(0.3, 0.01, 9.8, &fx_offset, &fy_offset);
  TiltTableSpecificForce(0.31, 0.0, 9.8, &fx_true, &fy_true);
  EXPECT_DOUBLE_EQ(fx_offset, fx_true);
  EXPECT_DOUBLE_EQ(fy_offset, fy_true);
}

TEST(AxisOutput, BaselineIsOnePlusScaleTimesForcePlusBias) {
  AxisErrors<double> errors;
  errors.bias = 0.07;
  errors.scale = -0.03;
  EXPECT_DOUBLE_EQ(AxisOutput(5.0, errors, 0.3, Phase::kCalibrationTest),
                   (1.0 - 0.03) * 5.0 + 0.07);
}

TEST(AxisOutput, EachTermActsOnlyWhereTheSpecSays) {
  AxisErrors<double> errors;
  errors.scale_nonlinearity = 0.002;
  EXPECT_DOUBLE_EQ(AxisOutput(3.0, errors, 0.0, Phase::kVehicleRun), 3.0 + 0.002 * 9.0);
  errors = AxisErrors<double>();
  errors.bias_drift = 0.1;  // calibration test only, times u
  EXPECT_DOUBLE_EQ(AxisOutput(3.0, errors, 0.25, Phase::kCalibrationTest), 3.0 + 0.025);
  EXPECT_DOUBLE_EQ(AxisOutput(3.0, errors, 0.25, Phase::kVehicleRun), 3.0);
  errors = AxisErrors<double>();
  errors.run_bias_shift = 0.2;  // vehicle run only
  EXPECT_DOUBLE_EQ(AxisOutput(3.0, errors, 0.25, Phase::kVehicleRun), 3.2);
  EXPECT_DOUBLE_EQ(AxisOutput(3.0, errors, 0.25, Phase::kCalibrationTest), 3.0);
}

TEST(DriftCoordinate, RunsFromMinusHalfToHalfWithZeroMean) {
  const int n = 11;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += DriftCoordinate(i, n);
  EXPECT_DOUBLE_EQ(DriftCoordinate(0, n), -0.5);
  EXPECT_DOUBLE_EQ(DriftCoordinate(n - 1, n), 0.5);
  EXPECT_NEAR(sum, 0.0, 1e-14);
  EXPECT_DOUBLE_EQ(DriftCoordinate(0, 1), 0.0);
}

TEST(ProjectOnSensingAxes, TiltsTheYAxisTowardX) {
  double along_x;
  double along_y;
  ProjectOnSensingAxes(2.0, 3.0, 0.01, &along_x, &along_y);
  EXPECT_DOUBLE_EQ(along_x, 2.0);
  EXPECT_DOUBLE_EQ(along_y, 3.0 * std::cos(0.01) + 2.0 * std::sin(0.01));
}

TEST(SensorModel, CompilesForCeresJetAndGivesExactDerivatives) {
  using Jet = ceres::Jet<double, 3>;
  const Jet offset(0.02, 0);
  const Jet scale(-0.03, 1);
  const Jet nonorthogonality(0.001, 2);
  Jet fx;
  Jet fy;
  TiltTableSpecificForce(Jet(0.7), offset, 9.8, &fx, &fy);
  Jet along_x;
  Jet along_y;
  ProjectOnSensingAxes(fx, fy, nonorthogonality, &along_x, &along_y);
  AxisErrors<Jet> errors;
  errors.scale = scale;
  const Jet output = AxisOutput(along_y, errors, 0.0, Phase::kCalibrationTest);
  // d output / d scale = f_along_y.
  EXPECT_NEAR(output.v[1], along_y.a, 1e-12);
  // d output / d delta = (1 + s) d f_along_y / d delta, with
  // f_along_y = -g cos(t) cos(eps) - g sin(t) sin(eps), t = theta + delta.
  const double t = 0.72;
  const double expected =
      (1.0 - 0.03) * (9.8 * std::sin(t) * std::cos(0.001) - 9.8 * std::cos(t) * std::sin(0.001));
  EXPECT_NEAR(output.v[0], expected, 1e-12);
}

TEST(InvertAxisOutput, InvertsTheForwardModelWithEveryRunTerm) {
  AxisErrors<double> errors;
  errors.bias = 0.08;
  errors.scale = -0.03;
  errors.scale_nonlinearity = 0.004;
  errors.run_bias_shift = -0.05;
  for (const double force : {-9.0, -1.0, 0.0, 0.5, 7.0}) {
    const double output = AxisOutput(force, errors, 0.0, Phase::kVehicleRun);
    EXPECT_NEAR(InvertAxisOutput(output, errors), force, 1e-12);
  }
  // Baseline: the inverse is (m - b) / (1 + s).
  AxisErrors<double> baseline;
  baseline.bias = 0.08;
  baseline.scale = -0.03;
  EXPECT_NEAR(InvertAxisOutput(2.0, baseline), (2.0 - 0.08) / 0.97, 1e-15);
}

TEST(CorrectRunSample, UndoesTheNonOrthogonalProjection) {
  SensorErrors<double> errors;
  errors.nonorthogonality = 0.02;
  errors.x.bias = 0.1;
  errors.y.scale = 0.01;
  double along_x;
  double along_y;
  ProjectOnSensingAxes(1.5, -2.5, 0.02, &along_x, &along_y);
  const double measured_x = AxisOutput(along_x, errors.x, 0.0, Phase::kVehicleRun);
  const double measured_y = AxisOutput(along_y, errors.y, 0.0, Phase::kVehicleRun);
  double ax;
  double ay;
  CorrectRunSample(measured_x, measured_y, errors, &ax, &ay);
  EXPECT_NEAR(ax, 1.5, 1e-13);
  EXPECT_NEAR(ay, -2.5, 1e-13);
}

double IntegrateEndpoint(const std::vector<double>& acceleration, double dt, double p0, double v0) {
  AxisKinematics<double> state{p0, v0};
  for (size_t j = 1; j < acceleration.size(); ++j) {
    TrapezoidalStep(dt, acceleration[j - 1], acceleration[j], &state);
  }
  return state.position;
}

TEST(EndpointWeights, ReproduceTheIntegrationByLinearity) {
  const int count = 257;
  const double dt = 0.02;
  std::vector<double> acceleration(count);
  for (int j = 0; j < count; ++j) acceleration[j] = std::sin(0.1 * j) + 0.3 * std::cos(0.37 * j);
  const std::vector<double> weights = EndpointWeights(count, dt);
  double weighted = 0.0;
  for (int j = 0; j < count; ++j) weighted += weights[j] * acceleration[j];
  const double duration = dt * (count - 1);
  EXPECT_NEAR(IntegrateEndpoint(acceleration, dt, 2.0, -1.5), 2.0 - 1.5 * duration + weighted,
              1e-11);
  // Each weight is the endpoint's response to a unit impulse in that sample.
  for (const int j : {0, 1, 100, count - 2, count - 1}) {
    std::vector<double> impulse(count, 0.0);
    impulse[j] = 1.0;
    EXPECT_NEAR(IntegrateEndpoint(impulse, dt, 0.0, 0.0), weights[j], 1e-14) << j;
  }
  // A constant acceleration a gives a T^2 / 2 exactly (the trapezoidal rule is exact).
  double sum = 0.0;
  for (double w : weights) sum += w;
  EXPECT_NEAR(sum, 0.5 * duration * duration, 1e-12);
}

}  // namespace
}  // namespace accelcal
