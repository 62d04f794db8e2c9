// The spec's model, term by term (../shared/spec/error-model.md), and its instantiation
// with ceres::Jet so that autodiff breakage shows at compile time.

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
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
  TiltTableSpecificForce(0.0, 9.8, &fx, &fy);
  EXPECT_NEAR(fx, 0.0, 1e-15);
  EXPECT_NEAR(fy, -9.8, 1e-15);
  TiltTableSpecificForce(kPi / 2, 9.8, &fx, &fy);
  EXPECT_NEAR(fx, -9.8, 1e-15);
  EXPECT_NEAR(fy, 0.0, 1e-14);
}

TEST(TrueTableAngle, AngleOffsetAddsToTheReportedAngle) {
  ModelParameters<double> p;
  EXPECT_DOUBLE_EQ(TrueTableAngle(0.3, p), 0.3);
  p[Parameter::kAngleOffset] = 0.01;
  EXPECT_DOUBLE_EQ(TrueTableAngle(0.3, p), 0.31);
}

TEST(AxisOutput, BaselineIsOnePlusScaleTimesForcePlusBias) {
  ModelParameters<double> p;
  p[Parameter::kBiasX] = 0.07;
  p[Parameter::kScaleX] = -0.03;
  p[Parameter::kBiasY] = 5.0;  // the other axis's terms do not reach x
  EXPECT_DOUBLE_EQ(AxisOutput(5.0, p, SensingAxis::kX, 0.3, Phase::kCalibrationTest),
                   (1.0 - 0.03) * 5.0 + 0.07);
}

TEST(AxisOutput, EachTermActsOnlyWhereTheSpecSays) {
  const SensingAxis x = SensingAxis::kX;
  ModelParameters<double> p;
  p[Parameter::kScaleNonlinearityX] = 0.002;
  EXPECT_DOUBLE_EQ(AxisOutput(3.0, p, x, 0.0, Phase::kVehicleRun), 3.0 + 0.002 * 9.0);
  p = ModelParameters<double>();
  p[Parameter::kBiasDriftX] = 0.1;  // calibration test only, times u
  EXPECT_DOUBLE_EQ(AxisOutput(3.0, p, x, 0.25, Phase::kCalibrationTest), 3.0 + 0.025);
  EXPECT_DOUBLE_EQ(AxisOutput(3.0, p, x, 0.25, Phase::kVehicleRun), 3.0);
  p = ModelParameters<double>();
  p[Parameter::kRunBiasShiftX] = 0.2;  // vehicle run only
  EXPECT_DOUBLE_EQ(AxisOutput(3.0, p, x, 0.25, Phase::kVehicleRun), 3.2);
  EXPECT_DOUBLE_EQ(AxisOutput(3.0, p, x, 0.25, Phase::kCalibrationTest), 3.0);
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
  ModelParameters<double> p;
  p[Parameter::kNonorthogonality] = 0.01;
  double along_x;
  double along_y;
  ProjectOnSensingAxes(2.0, 3.0, p, Phase::kVehicleRun, &along_x, &along_y);
  EXPECT_DOUBLE_EQ(along_x, 2.0);
  EXPECT_DOUBLE_EQ(along_y, 3.0 * std::cos(0.01) + 2.0 * std::sin(0.01));
}

TEST(SensorModel, CompilesForCeresJetAndGivesExactDerivatives) {
  using Jet = ceres::Jet<double, 3>;
  ModelParameters<Jet> p;
  p[Parameter::kAngleOffset] = Jet(0.02, 0);
  p[Parameter::kScaleY] = Jet(-0.03, 1);
  p[Parameter::kNonorthogonality] = Jet(0.001, 2);
  const Jet output = PredictCalibrationOutput(0.7, 0.0, SensingAxis::kY, 9.8, p);
  // f_along_y = -g cos(t) cos(eps) - g sin(t) sin(eps), t = theta + delta.
  const double t = 0.72;
  const double along_y = -9.8 * std::cos(t) * std::cos(0.001) - 9.8 * std::sin(t) * std::sin(0.001);
  EXPECT_NEAR(output.a, (1.0 - 0.03) * along_y, 1e-12);
  // d output / d scale = f_along_y.
  EXPECT_NEAR(output.v[1], along_y, 1e-12);
  // d output / d delta = (1 + s) d f_along_y / d delta.
  const double expected =
      (1.0 - 0.03) * (9.8 * std::sin(t) * std::cos(0.001) - 9.8 * std::cos(t) * std::sin(0.001));
  EXPECT_NEAR(output.v[0], expected, 1e-12);
  // d output / d eps = (1 + s) (g cos(t) sin(eps) - g sin(t) cos(eps)).
  EXPECT_NEAR(
      output.v[2],
      (1.0 - 0.03) * (9.8 * std::cos(t) * std::sin(0.001) - 9.8 * std::sin(t) * std::cos(0.001)),
      1e-12);
}

TEST(InvertAxisResponse, InvertsTheForwardModelWithEveryRunTerm) {
  ModelParameters<double> p;
  p[Parameter::kBiasX] = 0.08;
  p[Parameter::kScaleX] = -0.03;
  p[Parameter::kScaleNonlinearityX] = 0.004;
  p[Parameter::kRunBiasShiftX] = -0.05;
  const AxisPolynomial<double> response = AxisResponse(p, SensingAxis::kX, 0.0, Phase::kVehicleRun);
  for (const double force : {-9.0, -1.0, 0.0, 0.5, 7.0}) {
    const double output = AxisOutput(force, p, SensingAxis::kX, 0.0, Phase::kVehicleRun);
    EXPECT_NEAR(InvertAxisResponse(response, output), force, 1e-12);
  }
  // Baseline: the inverse is (m - b) / (1 + s).
  ModelParameters<double> baseline;
  baseline[Parameter::kBiasX] = 0.08;
  baseline[Parameter::kScaleX] = -0.03;
  EXPECT_NEAR(
      InvertAxisResponse(AxisResponse(baseline, SensingAxis::kX, 0.0, Phase::kVehicleRun), 2.0),
      (2.0 - 0.08) / 0.97, 1e-15);
}

TEST(RunCorrection, UndoesEveryRunTermAndTheProjection) {
  ModelParameters<double> p;
  p[Parameter::kNonorthogonality] = 0.02;
  p[Parameter::kBiasX] = 0.1;
  p[Parameter::kScaleY] = 0.01;
  p[Parameter::kScaleNonlinearityY] = -0.003;
  p[Parameter::kRunBiasShiftY] = 0.04;
  double measured_x;
  double measured_y;
  PredictRunOutputs(1.5, -2.5, p, &measured_x, &measured_y);
  double ax;
  double ay;
  const RunCorrection<double> correct(p);
  correct(measured_x, measured_y, &ax, &ay);
  EXPECT_NEAR(ax, 1.5, 1e-13);
  EXPECT_NEAR(ay, -2.5, 1e-13);
}

// The registry (models/effect_list.h) reproduces the spec's catalogue: its names, in its
// order, with the baseline first.
TEST(ParameterCatalogue, HasTheSpecsNamesInTheSpecsOrder) {
  const std::vector<std::string> spec = {"bias_x",
                                         "scale_x",
                                         "bias_y",
                                         "scale_y",
                                         "angle_offset",
                                         "nonorthogonality",
                                         "bias_drift_x",
                                         "bias_drift_y",
                                         "scale_nonlinearity_x",
                                         "scale_nonlinearity_y",
                                         "run_bias_shift_x",
                                         "run_bias_shift_y",
                                         "noise_variance_x",
                                         "noise_variance_y"};
  ASSERT_EQ(static_cast<size_t>(kParameterCount), spec.size());
  for (int i = 0; i < kParameterCount; ++i) {
    const ParameterInfo& info = ParameterCatalogue()[i];
    EXPECT_EQ(info.name, spec[i]);
    EXPECT_EQ(info.parameter, Parameter(i));
    EXPECT_EQ(FindParameter(spec[i]), &info);
    EXPECT_EQ(info.baseline, i < 4);
  }
  EXPECT_STREQ(Info(Parameter::kBiasDriftY).meaning,
               "y bias change from the first to the last calibration sample");
  EXPECT_EQ(FindParameter("bias"), nullptr);
}

// Each effect changes the tilt test's prediction exactly when it declares it acts there,
// and the run's outputs exactly when it acts in the run: the declaration that places it in
// the residuals' blocks and the term itself agree.
TEST(Effects, EachActsExactlyWhereItDeclares) {
  ModelParameters<double> base;
  base[Parameter::kBiasX] = 0.07;
  base[Parameter::kScaleY] = 0.01;
  for (const ParameterInfo& info : ParameterCatalogue()) {
    if (IsNoiseRatio(info.parameter)) continue;
    SCOPED_TRACE(info.name);
    ModelParameters<double> moved = base;
    moved[info.parameter] += info.example_size > 0.0 ? info.example_size : 0.01;
    double test_change = 0.0;
    for (const double theta : {0.3, 1.2, 2.5, 4.0, 5.5}) {
      for (const SensingAxis axis : {SensingAxis::kX, SensingAxis::kY}) {
        test_change += std::abs(PredictCalibrationOutput(theta, 0.4, axis, 9.8, moved) -
                                PredictCalibrationOutput(theta, 0.4, axis, 9.8, base));
      }
    }
    double run_change = 0.0;
    for (const double ax : {-2.0, 0.5, 3.0}) {
      double base_x, base_y, moved_x, moved_y;
      PredictRunOutputs(ax, 1.0 - ax, base, &base_x, &base_y);
      PredictRunOutputs(ax, 1.0 - ax, moved, &moved_x, &moved_y);
      run_change += std::abs(moved_x - base_x) + std::abs(moved_y - base_y);
    }
    EXPECT_EQ(test_change > 1e-9, ActsOn(info.parameter, Phase::kCalibrationTest, true, {}));
    EXPECT_EQ(run_change > 1e-9, ActsOn(info.parameter, Phase::kVehicleRun, true, {}));
    // The residuals' blocks follow the declaration.
    const auto blocks_x = CalibrationParameters(SensingAxis::kX);
    const auto blocks_y = CalibrationParameters(SensingAxis::kY);
    const auto run = RunParameters();
    const bool in_x = std::find(blocks_x.begin(), blocks_x.end(), info.parameter) != blocks_x.end();
    const bool in_y = std::find(blocks_y.begin(), blocks_y.end(), info.parameter) != blocks_y.end();
    const bool in_run = std::find(run.begin(), run.end(), info.parameter) != run.end();
    EXPECT_EQ(in_x || in_y, test_change > 1e-9);
    EXPECT_EQ(in_run, run_change > 1e-9);
  }
}

// The run's correction inverts the run's outputs at parameters with every effect present.
TEST(RunCorrection, InvertsPredictRunOutputsWithEveryEffect) {
  ModelParameters<double> p;
  for (const ParameterInfo& info : ParameterCatalogue()) {
    if (!IsNoiseRatio(info.parameter))
      p[info.parameter] += info.example_size > 0.0 ? 3.0 * info.example_size : 0.02;
  }
  const RunCorrection<double> correct(p);
  for (const double ax : {-6.0, -0.5, 0.0, 2.0, 8.0}) {
    double measured_x, measured_y, back_x, back_y;
    PredictRunOutputs(ax, 0.5 * ax - 1.0, p, &measured_x, &measured_y);
    correct(measured_x, measured_y, &back_x, &back_y);
    EXPECT_NEAR(back_x, ax, 1e-12);
    EXPECT_NEAR(back_y, 0.5 * ax - 1.0, 1e-12);
  }
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
