// The calibration file (io/calibration_file.h): written and read back unchanged, refused in
// one line when it does not say what it claims; and the correction apply makes with it
// (estimation/tilt_table/calibration_correction.h): the inverse of the model, with a sigma that
// matches the spread of corrections made with calibrations from independent tilt tests.

#include "io/calibration_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "estimation/tilt_table/calibration_correction.h"
#include "estimation/tilt_table/linear_ls.h"
#include "models/effects.h"
#include "simulation/simulator.h"
#include "test_support.h"

namespace accelcal {
namespace {

CalibrationRecord ExampleRecord() {
  CalibrationRecord record;
  GeometryInfo geometry;
  EXPECT_TRUE(GeometryOf("two_axis", "m/s^2", &geometry).ok());
  record.parameter_order = geometry.parameters;
  record.values = Eigen::Vector4d(0.0767, -0.0301, -0.0175, 0.0100);
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
  covariance.diagonal() << 1.25e-5, 2.6e-7, 3.2e-5, 6.7e-7;
  covariance(0, 1) = covariance(1, 0) = 1e-7;
  record.covariance = covariance;
  record.gravity_mps2 = 9.8;
  record.noise_variance = {0.25, 0.64};
  record.noise_variance_from = "datos.txt";
  record.fit = {{"samples", 20001}};
  return record;
}

TEST(CalibrationFile, ReadsBackWhatItWroteToTheLastBit) {
  const CalibrationRecord written = ExampleRecord();
  const std::string text = CalibrationJson(written).dump(2);
  CalibrationRecord read;
  const Status status = ParseCalibration(text, "cal.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(read.parameter_order, written.parameter_order);
  EXPECT_EQ(read.values, written.values);
  EXPECT_EQ(read.covariance, written.covariance);
  EXPECT_EQ(read.noise_variance, written.noise_variance);
  EXPECT_EQ(read.gravity_mps2, 9.8);
  EXPECT_EQ(read.fit["samples"], 20001);
  EXPECT_EQ(read.IndexOf("scale_y"), 3);
}

// Issue 30, item 5: the poorly determined parameters round-trip; a file without the key (written
// before it) or with null (not assessed) is read as not assessed; an entry that names no
// parameter of the file is refused.
TEST(CalibrationFile, PoorlyDeterminedRoundTripsAndIsOptional) {
  CalibrationRecord written = ExampleRecord();
  written.poorly_determined = nlohmann::json::array(
      {{{"parameter", "scale_y"},
        {"reason", "sigma 0.02 > 0.001"},
        {"sigma", 0.02},
        {"threshold", 0.001},
        {"sigma_over_threshold", true},
        {"correlated_with",
         nlohmann::json::array({{{"parameter", "bias_y"}, {"correlation", 0.995}}})},
        {"suggestion", "poses with the y axis near +g or -g"}}});
  const nlohmann::json json = CalibrationJson(written);
  CalibrationRecord read;
  Status status = ParseCalibration(json.dump(2), "cal.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(read.poorly_determined, written.poorly_determined);

  nlohmann::json without = json;
  without.erase("poorly_determined");
  status = ParseCalibration(without.dump(), "cal.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_TRUE(read.poorly_determined.is_null());
  const nlohmann::json none = CalibrationJson(ExampleRecord());
  EXPECT_TRUE(none["poorly_determined"].is_null());
  status = ParseCalibration(none.dump(), "cal.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_TRUE(read.poorly_determined.is_null());

  for (const nlohmann::json& bad :
       {nlohmann::json("scale_y"), nlohmann::json::array({{{"parameter", "gain_q"}}}),
        nlohmann::json::array({{{"reason", "no name"}}})}) {
    nlohmann::json damaged = json;
    damaged["poorly_determined"] = bad;
    status = ParseCalibration(damaged.dump(), "cal.json", &read);
    ASSERT_FALSE(status.ok()) << bad.dump();
    EXPECT_EQ(status.message().rfind("cal.json: ", 0), 0u) << status.message();
    EXPECT_NE(status.message().find("poorly_determined"), std::string::npos) << status.message();
  }
}

// Each damaged file is refused with a message naming what is wrong.
TEST(CalibrationFile, RefusesWhatDoesNotSayWhatItClaims) {
  const nlohmann::json good = CalibrationJson(ExampleRecord());
  struct Damage {
    const char* pointer;
    nlohmann::json value;
    const char* expected;
  };
  const Damage damages[] = {
      {"/format", "something-else", "not an accelcal calibration file"},
      {"/format_version", 2, "format_version 2, but this accelcal reads version 1; update"},
      {"/model/geometry", "four_axis", "unknown sensor geometry 'four_axis'"},
      {"/units/bias_x", "mg", "units/bias_x must be \"m/s^2\""},
      {"/parameters/scale_y", "0.01", "parameters/scale_y must be a number"},
      {"/parameter_order/0", "scale_x",
       "parameter_order must be [bias_x, scale_x, bias_y, scale_y]"},
      {"/covariance/0/1", 5e-7, "covariance is not symmetric (scale_x, bias_x)"},
      {"/covariance/1/1", -1.0, "the variance of scale_x is not positive"},
      {"/covariance/0/1", nullptr, "covariance[0][1] is not a finite number"},
      {"/gravity_mps2", 981.0, "gravity_mps2 = 981 is outside [1, 100]"},
      {"/noise_variance/y", 0.0, "noise_variance/y = 0 is outside"},
      {"/parameters/scale_x", -0.95, "1 + scale_x is not above 0.1"},
  };
  for (const Damage& damage : damages) {
    SCOPED_TRACE(damage.pointer);
    nlohmann::json damaged = good;
    damaged[nlohmann::json::json_pointer(damage.pointer)] = damage.value;
    CalibrationRecord record;
    const Status status = ParseCalibration(damaged.dump(), "cal.json", &record);
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.message().rfind("cal.json: ", 0), 0u) << status.message();
    EXPECT_NE(status.message().find(damage.expected), std::string::npos) << status.message();
  }
  // Symmetric, positive variances, but not a covariance: correlation 2.
  nlohmann::json damaged = good;
  const double c = 2.0 * std::sqrt(1.25e-5 * 2.6e-7);
  damaged["covariance"][0][1] = damaged["covariance"][1][0] = c;
  CalibrationRecord record;
  const Status status = ParseCalibration(damaged.dump(), "cal.json", &record);
  EXPECT_NE(status.message().find("not positive semi-definite"), std::string::npos)
      << status.message();
  // A key given twice.
  const Status twice = ParseCalibration(R"({"format": "a", "format": "b"})", "cal.json", &record);
  EXPECT_NE(twice.message().find("given twice"), std::string::npos) << twice.message();
}

TEST(CorrectBaseline, InvertsTheMeasurementModel) {
  const Eigen::Vector4d parameters(0.08, -0.03, -0.02, 0.01);
  const double a_x = 1.7, a_y = -9.1;
  const double m_x = (1 + parameters[1]) * a_x + parameters[0];
  const double m_y = (1 + parameters[3]) * a_y + parameters[2];
  const CorrectedSample sample = CorrectBaseline(parameters, Eigen::Matrix4d::Zero(), m_x, m_y);
  EXPECT_NEAR(sample.acceleration.x(), a_x, 1e-14);
  EXPECT_NEAR(sample.acceleration.y(), a_y, 1e-14);
  EXPECT_EQ(sample.covariance, Eigen::Matrix2d::Zero());
}

// Calibrate from 2000 independent simulated tilt tests, correct one fixed output with each:
// the corrections' spread is what CorrectBaseline's sigma says (within 10%, far outside the
// ~3% sampling error of a standard deviation from 2000 draws), on both axes and at outputs
// where the bias or the scale term dominates.
TEST(CorrectBaseline, SigmaMatchesTheSpreadOverIndependentCalibrations) {
  TiltSchedule schedule;
  schedule.sample_count = 400;
  const SimulationTruth truth = CourseTableOneTruth();
  LinearLsOptions options;
  options.noise_variance_x = truth.stated_noise_variance_x;
  options.noise_variance_y = truth.stated_noise_variance_y;
  const double outputs[2][2] = {{0.3, -0.2}, {9.5, -9.6}};
  constexpr int kTrials = 2000;
  for (const auto& output : outputs) {
    SCOPED_TRACE(output[0]);
    Eigen::Vector2d sum = Eigen::Vector2d::Zero(), sum2 = Eigen::Vector2d::Zero();
    Eigen::Vector2d reported = Eigen::Vector2d::Zero();
    for (int trial = 0; trial < kTrials; ++trial) {
      const CalibrationTest test = SimulateTiltTest(schedule, truth, 11, trial);
      BaselineFit fit;
      ASSERT_TRUE(EstimateLinearLs(test, options, &fit).ok());
      const CorrectedSample sample =
          CorrectBaseline(fit.parameters, fit.covariance, output[0], output[1]);
      sum += sample.acceleration;
      sum2 += sample.acceleration.cwiseAbs2();
      reported += sample.covariance.diagonal().cwiseSqrt() / kTrials;
    }
    const Eigen::Vector2d mean = sum / kTrials;
    const Eigen::Vector2d spread =
        ((sum2 - kTrials * mean.cwiseAbs2()) / (kTrials - 1)).cwiseSqrt();
    for (int axis = 0; axis < 2; ++axis) {
      std::printf("output (%g, %g), axis %d: reported sigma %.4g, spread %.4g, ratio %.3f\n",
                  output[0], output[1], axis, reported[axis], spread[axis],
                  reported[axis] / spread[axis]);
      EXPECT_NEAR(reported[axis] / spread[axis], 1.0, 0.1) << "axis " << axis;
    }
  }
}

}  // namespace
}  // namespace accelcal
