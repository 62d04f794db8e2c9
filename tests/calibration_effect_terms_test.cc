// The calibration is the model discovery settled on (issue 44, item 7): a calibration file of
// format_version 2 carries effect terms after the 9 (the triad's) and the 12 (its gyroscope's),
// with the baseline beside them; its reader refuses what would apply them wrongly or not at all;
// the correction with effect terms inverts the model's prediction (against the closed form of
// models/triad.h for a second-order scale term) and its covariance is the 9-parameter one's when
// there are none; the gyroscope's correction is GyroscopeCorrectedRate's.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "estimation/tilt_table/calibration_correction.h"
#include "gyroscope_calibration_example.h"
#include "io/calibration_file.h"
#include "models/triad_correction.h"
#include "reporting/calibrate_imu_report.h"
#include "simulation/random.h"
#include "simulation/triad_simulator.h"
#include "test_support.h"
#include "triad_test_session.h"

namespace accelcal {
namespace {

int Coefficient(const std::string& name) {
  const int c = TriadEffectCoefficientIndex(name);
  EXPECT_GE(c, 0) << name;
  return c;
}

// The example triad with second-order scale terms and an offset drift, and its baseline.
CalibrationRecord TriadRecordWithTerms() {
  CalibrationRecord record = testing::ExampleTriadRecord();
  CalibrationBaseline& baseline = record.baseline;
  baseline.parameter_order = record.parameter_order;
  baseline.values = record.values;
  baseline.values[kTriadOffsetX] += 1.5;
  baseline.covariance = record.covariance;
  const std::vector<std::string> terms = {"scale_nonlinearity_x", "scale_nonlinearity_y",
                                          "scale_nonlinearity_z", "offset_drift_x",
                                          "offset_drift_y",       "offset_drift_z"};
  const std::vector<double> values = {2e-4, -1e-4, 3e-4, 1e-3, -2e-3, 5e-4};
  const int n = kTriadParameterCount + static_cast<int>(terms.size());
  record.values.conservativeResize(n);
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(n, n);
  covariance.topLeftCorner(kTriadParameterCount, kTriadParameterCount) = record.covariance;
  for (size_t t = 0; t < terms.size(); ++t) {
    record.parameter_order.push_back(terms[t]);
    record.values[kTriadParameterCount + t] = values[t];
    covariance(kTriadParameterCount + t, kTriadParameterCount + t) = t < 3 ? 1e-10 : 1e-8;
  }
  // A correlation between gain_x and its second-order term, as a fit gives.
  const int k2x = kTriadParameterCount;
  covariance(kTriadGainX, k2x) = covariance(k2x, kTriadGainX) =
      0.5 * std::sqrt(covariance(kTriadGainX, kTriadGainX) * covariance(k2x, k2x));
  record.covariance = covariance;
  return record;
}

std::string Written(const CalibrationRecord& record) { return CalibrationJson(record).dump(2); }

Status Parsed(const nlohmann::json& json, CalibrationRecord* read) {
  return ParseCalibration(json.dump(), "cal.json", read);
}

TEST(CalibrationEffectTerms, ATriadsTermsAndBaselineRoundTripAsVersion2) {
  const CalibrationRecord record = TriadRecordWithTerms();
  const nlohmann::json json = nlohmann::json::parse(Written(record));
  EXPECT_EQ(json.at("format_version"), 2);
  EXPECT_EQ(json.at("model").at("effects"), nlohmann::json({"misalignment", "gain", "offset",
                                                            "scale_nonlinearity", "offset_drift"}));
  const nlohmann::json& terms = json.at("model").at("effect_terms");
  ASSERT_EQ(terms.size(), 2u);
  EXPECT_EQ(terms[0].at("effect"), "scale_nonlinearity");
  EXPECT_TRUE(terms[0].at("applied_by_apply").get<bool>());
  EXPECT_EQ(terms[1].at("effect"), "offset_drift");
  EXPECT_FALSE(terms[1].at("applied_by_apply").get<bool>());
  EXPECT_EQ(json.at("units").at("offset_drift_x"), "count/s");
  EXPECT_EQ(json.at("units").at("scale_nonlinearity_x"), "1/(m/s^2)");
  CalibrationRecord read;
  const Status status = Parsed(json, &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(read.parameter_order, record.parameter_order);
  EXPECT_EQ((read.values - record.values).norm(), 0.0);
  EXPECT_EQ((read.covariance - record.covariance).norm(), 0.0);
  ASSERT_TRUE(read.baseline.present());
  EXPECT_EQ((read.baseline.values - record.baseline.values).norm(), 0.0);
  EXPECT_EQ(EffectTermNames(read).size(), 6u);

  // A reader of the 9 is refused, naming the terms; the baseline's reader and the model's read.
  TriadParameters parameters;
  Eigen::MatrixXd covariance;
  TriadOutputUnit unit;
  EXPECT_ERROR_CONTAINS(TriadCalibration(read, "cal.json", &parameters, &covariance, &unit),
                        "scale_nonlinearity_x");
  bool from_baseline = false;
  ASSERT_TRUE(
      TriadBaselineCalibration(read, "cal.json", &parameters, &covariance, &unit, &from_baseline)
          .ok());
  EXPECT_TRUE(from_baseline);
  EXPECT_EQ(parameters[kTriadOffsetX], record.baseline.values[kTriadOffsetX]);
  TriadCalibrationModel model;
  ASSERT_TRUE(TriadCalibrationModelOf(read, "cal.json", &model).ok());
  EXPECT_EQ(model.effects_applied, std::vector<int>({Coefficient("scale_nonlinearity_x"),
                                                     Coefficient("scale_nonlinearity_y"),
                                                     Coefficient("scale_nonlinearity_z")}));
  EXPECT_EQ(model.effects_not_applied.size(), 3u);
  EXPECT_EQ(model.effects[Coefficient("scale_nonlinearity_z")], 3e-4);
  EXPECT_EQ(model.effects[Coefficient("offset_drift_x")], 0.0);  // carried, not applied
  const int k2x = kTriadParameterCount + Coefficient("scale_nonlinearity_x");
  EXPECT_EQ(model.covariance(kTriadGainX, k2x), record.covariance(kTriadGainX, 9));
  EXPECT_EQ(model.covariance(k2x, k2x), 1e-10);
  // A record without terms: version 1, no baseline, as before.
  const nlohmann::json plain = nlohmann::json::parse(Written(testing::ExampleTriadRecord()));
  EXPECT_EQ(plain.at("format_version"), 1);
  EXPECT_TRUE(plain.at("baseline").is_null());
}

TEST(CalibrationEffectTerms, RefusesTermsThatWouldBeMisread) {
  const nlohmann::json good = nlohmann::json::parse(Written(TriadRecordWithTerms()));
  CalibrationRecord read;
  nlohmann::json json = good;
  json["format_version"] = 1;  // a version-1 file has no terms
  EXPECT_ERROR_CONTAINS(Parsed(json, &read), "format_version 2");
  json = good;
  json["parameter_order"][9] = "scale_cubic_x";  // a term this accelcal does not know
  EXPECT_ERROR_CONTAINS(Parsed(json, &read), "not an effect term this accelcal knows");
  json = good;
  std::swap(json["parameter_order"][9], json["parameter_order"][10]);  // out of order
  EXPECT_ERROR_CONTAINS(Parsed(json, &read), "in the registry's order");
  json = good;
  json["baseline"] = nullptr;  // terms without the model without them
  EXPECT_ERROR_CONTAINS(Parsed(json, &read), "baseline must be an object");
  json = good;
  json["model"]["effects"] = {"misalignment", "gain", "offset"};
  EXPECT_ERROR_CONTAINS(Parsed(json, &read), "model/effects");
  json = good;
  json["baseline"]["parameters"]["gain_x"] = "x";
  EXPECT_ERROR_CONTAINS(Parsed(json, &read), "baseline/parameters/gain_x");
  // A baseline without terms, and version 2 without terms.
  nlohmann::json plain = nlohmann::json::parse(Written(testing::ExampleTriadRecord()));
  json = plain;
  json["baseline"] = good["baseline"];
  EXPECT_ERROR_CONTAINS(Parsed(json, &read), "carries no effect term");
  json = plain;
  json["format_version"] = 2;
  EXPECT_ERROR_CONTAINS(Parsed(json, &read), "carries none");
  json = plain;
  json["format_version"] = 3;
  EXPECT_ERROR_CONTAINS(Parsed(json, &read), "update accelcal");
}

TEST(CalibrationEffectTerms, TheCorrectionInvertsThePredictionAndMatchesTheClosedForm) {
  CalibrationRecord record = TriadRecordWithTerms();
  // Second-order terms 50 times the sizes seen (1e-2 1/(m/s^2)): the steps still settle.
  record.values[9] = 1e-2;
  record.values[10] = -5e-3;
  record.values[11] = 2e-3;
  TriadCalibrationModel model;
  ASSERT_TRUE(TriadCalibrationModelOf(record, "cal.json", &model).ok());
  const TriadScaleNonlinearity k2 = {1e-2, -5e-3, 2e-3};
  RandomSource random(7);
  double worst = 0.0;
  double worst_sigma = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    // A force of up to 2 g in any direction, its output by the model's prediction.
    double force[3];
    for (double& f : force) f = 9.81 * random.StandardNormal();
    double raw[3];
    const double direction[3] = {force[0] / model.gravity_mps2, force[1] / model.gravity_mps2,
                                 force[2] / model.gravity_mps2};
    ASSERT_TRUE(TriadPredictOutput(model.parameters.data(), model.effects.data(),
                                   TriadPoseContext(), direction, model.gravity_mps2, raw));
    CorrectedTriadSample sample;
    ASSERT_TRUE(CorrectTriad(model, {raw[0], raw[1], raw[2]}, &sample));
    double closed[3];
    ASSERT_TRUE(TriadSpecificForce(model.parameters.data(), k2.data(), raw, closed));
    for (int k = 0; k < 3; ++k) {
      worst = std::max(worst, std::abs(sample.acceleration[k] - force[k]));
      worst = std::max(worst, std::abs(sample.acceleration[k] - closed[k]));
    }
    // The covariance is J C J^T with J of the closed form (finite differences in gain_x and
    // k2_x, the correlated pair).
    const auto closed_x = [&](double gain_x, double k2_x) {
      TriadParameters p = model.parameters;
      p[kTriadGainX] = gain_x;
      TriadScaleNonlinearity terms = k2;
      terms[0] = k2_x;
      double f[3];
      TriadSpecificForce(p.data(), terms.data(), raw, f);
      return f[0];
    };
    const double h_gain = 1e-6 * model.parameters[kTriadGainX];
    const double h_k2 = 1e-7;
    Eigen::Matrix<double, 1, 2> jacobian;
    jacobian << (closed_x(model.parameters[kTriadGainX] + h_gain, k2[0]) -
                 closed_x(model.parameters[kTriadGainX] - h_gain, k2[0])) /
                    (2 * h_gain),
        (closed_x(model.parameters[kTriadGainX], k2[0] + h_k2) -
         closed_x(model.parameters[kTriadGainX], k2[0] - h_k2)) /
            (2 * h_k2);
    Eigen::Matrix2d pair;
    const int k2x = kTriadParameterCount + Coefficient("scale_nonlinearity_x");
    pair << model.covariance(kTriadGainX, kTriadGainX), model.covariance(kTriadGainX, k2x),
        model.covariance(k2x, kTriadGainX), model.covariance(k2x, k2x);
    // a_x's variance from these two alone (the others' variances set to 0).
    TriadCalibrationModel two = model;
    two.covariance.setZero();
    two.covariance(kTriadGainX, kTriadGainX) = pair(0, 0);
    two.covariance(kTriadGainX, k2x) = two.covariance(k2x, kTriadGainX) = pair(0, 1);
    two.covariance(k2x, k2x) = pair(1, 1);
    CorrectedTriadSample from_two;
    ASSERT_TRUE(CorrectTriad(two, {raw[0], raw[1], raw[2]}, &from_two));
    const double expected = (jacobian * pair * jacobian.transpose())(0, 0);
    worst_sigma =
        std::max(worst_sigma, std::abs(std::sqrt(from_two.covariance(0, 0)) - std::sqrt(expected)) /
                                  std::sqrt(expected));
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_sigma, 1e-5);

  // Without terms, the correction is the 9-parameter one to the last bit.
  CalibrationRecord plain = testing::ExampleTriadRecord();
  TriadCalibrationModel nine;
  ASSERT_TRUE(TriadCalibrationModelOf(plain, "cal.json", &nine).ok());
  EXPECT_FALSE(nine.has_effects());
  const std::array<double, 3> output = {32900.0, 28000.0, 36100.0};
  CorrectedTriadSample with_model;
  ASSERT_TRUE(CorrectTriad(nine, output, &with_model));
  TriadParameters parameters;
  for (int p = 0; p < kTriadParameterCount; ++p) parameters[p] = plain.values[p];
  const CorrectedTriadSample direct = CorrectTriad(parameters, plain.covariance, output);
  EXPECT_EQ(with_model.acceleration, direct.acceleration);
  EXPECT_EQ(with_model.covariance, direct.covariance);
}

// The accelerometer's side end to end (issue 44, item 7): a simulated triad with a second-order
// scale term on z (1e-4 1/(m/s^2), 4 counts at 1 g), the session of TriadDiscovery's own test.
// Discovery keeps it; the report's calibration is its final fit, the 9-parameter fit beside it;
// the file carries the term; its correction applies it, so that the poses' corrected |a| is g
// within their noise, where the baseline's misses by the term's share on the tilted poses.
TEST(CalibrationEffectTerms, TheAccelerometersCalibrationIsTheModelDiscoverySettledOn) {
  TriadSimulationOptions simulation = testing::TriadTestSimulationOptions();
  const int k2_z = TriadEffectCoefficientIndex("scale_nonlinearity_z");
  simulation.effects[k2_z] = 1e-4;
  RandomSource random(43, 1);
  const std::vector<std::array<double, 3>> directions = RandomPoseDirections(30, &random);
  const std::vector<TriadPoseMean> poses = SimulateTriadPoses(simulation, directions, &random);
  TriadSessionCalibration session;
  session.discovery_options = testing::TriadTestDiscovery(0.01);
  ASSERT_TRUE(DiscoverTriad(poses, session.discovery_options, &session.discovery).ok());
  session.ml = session.discovery.baseline;
  session.ml_options = session.discovery_options.fit;
  ASSERT_TRUE(TriadDiscoveryKeptEffects(session.discovery)) << session.discovery.verdict;
  CalibrateImuReport report;
  report.unit = TriadOutputUnit::kCount;
  TakeSessionCalibration(session, &report);
  ASSERT_TRUE(report.has_ml_baseline);
  EXPECT_EQ(report.ml.effects_estimated, report.discovery.final_fit.effects_estimated);
  EXPECT_EQ(report.ml_baseline.parameters, report.discovery.baseline.parameters);
  const CalibrationRecord record = TriadCalibrationRecord(report, DataSource());
  const std::vector<std::string> terms = EffectTermNames(record);
  EXPECT_NE(std::find(terms.begin(), terms.end(), "scale_nonlinearity_z"), terms.end());
  CalibrationRecord read;
  const Status status = Parsed(nlohmann::json::parse(Written(record)), &read);
  ASSERT_TRUE(status.ok()) << status.message();
  TriadCalibrationModel model;
  ASSERT_TRUE(TriadCalibrationModelOf(read, "cal.json", &model).ok());
  EXPECT_EQ(model.effects_applied, std::vector<int>({k2_z}));
  EXPECT_LT(
      std::abs(model.effects[k2_z] - 1e-4),
      3.0 * std::sqrt(model.covariance(kTriadParameterCount + k2_z, kTriadParameterCount + k2_z)));
  // |a| over the poses against g: the model's and the baseline's (which absorbs the term's even
  // share into offset_z and gain_z, not its share on the tilted poses).
  TriadCalibrationModel baseline;
  for (int p = 0; p < kTriadParameterCount; ++p) baseline.parameters[p] = read.baseline.values[p];
  baseline.covariance = Eigen::MatrixXd::Zero(kTriadCorrectionUnknowns, kTriadCorrectionUnknowns);
  baseline.gravity_mps2 = model.gravity_mps2;
  double settled = 0.0, nine = 0.0;
  int count = 0;
  for (size_t p = 0; p < poses.size(); ++p) {
    CorrectedTriadSample a, b;
    ASSERT_TRUE(CorrectTriad(model, poses[p].mean, &a));
    ASSERT_TRUE(CorrectTriad(baseline, poses[p].mean, &b));
    settled += std::pow(a.acceleration.norm() - simulation.gravity_mps2, 2);
    nine += std::pow(b.acceleration.norm() - simulation.gravity_mps2, 2);
    ++count;
  }
  ASSERT_GT(count, 2);
  std::printf("  rms |a| - g over %d poses: %.3g m/s^2 settled, %.3g baseline\n", count,
              std::sqrt(settled / count), std::sqrt(nine / count));
  EXPECT_LT(std::sqrt(settled / count), 0.5 * std::sqrt(nine / count))
      << std::sqrt(settled / count) << " " << std::sqrt(nine / count);
}

TEST(CalibrationEffectTerms, AGyroscopeSectionsTermsRoundTripAndAreApplied) {
  CalibrationRecord record = testing::ExampleTriadRecord();
  const std::vector<int> terms = {0, 4, 8, 12};  // g_sensitivity xx, yy, zz; nonlinearity x
  GyroscopeEffectCoefficients values{};
  values[0] = 2e-4;
  values[4] = -1e-4;
  values[8] = 3e-4;
  values[12] = 1e-3;
  testing::AddExampleGyroscopeTerms(terms, values, {1e-12, 1e-12, 1e-12, 1e-12}, &record);
  const nlohmann::json json = nlohmann::json::parse(Written(record));
  EXPECT_EQ(json.at("format_version"), 2);  // the accelerometer has no terms; its gyroscope has
  EXPECT_EQ(json.at("gyroscope").at("model").at("effects"),
            nlohmann::json({"g_sensitivity", "scale_nonlinearity"}));
  EXPECT_EQ(json.at("gyroscope").at("units").at("gyroscope_g_sensitivity_yy"), "(rad/s)/(m/s^2)");
  CalibrationRecord read;
  const Status status = Parsed(json, &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(
      EffectTermNames(read.gyroscope),
      std::vector<std::string>({"gyroscope_g_sensitivity_xx", "gyroscope_g_sensitivity_yy",
                                "gyroscope_g_sensitivity_zz", "gyroscope_scale_nonlinearity_x"}));
  GyroscopeParameters parameters;
  GyroscopeOffset offset;
  Eigen::MatrixXd twelve;
  GyroscopeOutputUnit unit;
  EXPECT_ERROR_CONTAINS(GyroscopeCalibration(read.gyroscope, &parameters, &offset, &twelve, &unit),
                        "gyroscope_g_sensitivity_xx");
  GyroscopeCalibrationModel model;
  ASSERT_TRUE(GyroscopeCalibrationModelOf(read.gyroscope, &model).ok());
  EXPECT_TRUE(model.needs_specific_force());
  const std::array<double, 3> output = {500.0, -300.0, 1200.0};
  const Eigen::Vector3d force(1.0, -2.0, 9.5);
  const CorrectedGyroscopeSample sample = CorrectGyroscope(model, output, force);
  double expected[3];
  const double f[3] = {force.x(), force.y(), force.z()};
  GyroscopeCorrectedRate(model.parameters.data(), model.offset.data(), values.data(), output.data(),
                         f, expected);
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(sample.angular_rate[k], expected[k]);
  // The g-sensitivity's share is there: the 12-parameter rate differs by about G f.
  const CorrectedGyroscopeSample without = CorrectGyroscope(
      model.parameters, model.offset, testing::ExampleGyroscopeCovariance(), output);
  EXPECT_NEAR(without.angular_rate.z() - sample.angular_rate.z(), 3e-4 * 9.5, 1e-7);
  // The terms' variance reaches the rate's.
  EXPECT_GT(sample.covariance(2, 2), without.covariance(2, 2));
}

// A gyroscope section carrying a time offset (GyroscopeTimeOffsetEffect::kInfo.session_only):
// written with applied_by_apply false and its reason, read back as carried but not applied, and
// the correction the same as without it.
TEST(CalibrationEffectTerms, AGyroscopeTimeOffsetIsCarriedNotApplied) {
  constexpr int kTimeOffset = GyroscopeEffectFirstOf<GyroscopeTimeOffsetEffect>();
  CalibrationRecord record = testing::ExampleTriadRecord();
  const std::vector<int> terms = {0, kTimeOffset};  // g_sensitivity xx; the time offset
  GyroscopeEffectCoefficients values{};
  values[0] = 2e-4;
  values[kTimeOffset] = 3e-3;
  testing::AddExampleGyroscopeTerms(terms, values, {1e-12, 1e-8}, &record);
  const nlohmann::json json = nlohmann::json::parse(Written(record));
  const nlohmann::json& effect_terms = json.at("gyroscope").at("model").at("effect_terms");
  ASSERT_EQ(effect_terms.size(), 2u) << effect_terms.dump(1);
  EXPECT_EQ(effect_terms[1].at("effect"), "time_offset");
  EXPECT_FALSE(effect_terms[1].at("applied_by_apply").get<bool>());
  EXPECT_NE(effect_terms[1].at("why_not_applied").get<std::string>().find("logging chain"),
            std::string::npos);
  EXPECT_TRUE(effect_terms[0].at("applied_by_apply").get<bool>());
  EXPECT_EQ(json.at("gyroscope").at("units").at("gyroscope_time_offset"), "s");
  CalibrationRecord read;
  ASSERT_TRUE(Parsed(json, &read).ok());
  GyroscopeCalibrationModel model;
  ASSERT_TRUE(GyroscopeCalibrationModelOf(read.gyroscope, &model).ok());
  EXPECT_EQ(model.effects_in_file, std::vector<int>({0}));
  EXPECT_EQ(model.effects_not_applied, std::vector<int>({kTimeOffset}));
  EXPECT_EQ(model.effects[kTimeOffset], 0.0);
  // Applied as the model with the g-sensitivity alone.
  const std::array<double, 3> output = {500.0, -300.0, 1200.0};
  const Eigen::Vector3d force(1.0, -2.0, 9.5);
  const CorrectedGyroscopeSample sample = CorrectGyroscope(model, output, force);
  GyroscopeEffectCoefficients alone{};
  alone[0] = 2e-4;
  double expected[3];
  const double f[3] = {force.x(), force.y(), force.z()};
  GyroscopeCorrectedRate(model.parameters.data(), model.offset.data(), alone.data(), output.data(),
                         f, expected);
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(sample.angular_rate[k], expected[k]);
}

// The Earth's vertical rate is a registered gyroscope effect (the fit's effect block holds it),
// but the session's world, not the sensor's: no calibration is written with it, and a file that
// lists it is refused, naming it.
TEST(CalibrationEffectTerms, TheEarthsRateIsNeverATermOfACalibration) {
  constexpr int kTimeOffset = GyroscopeEffectFirstOf<GyroscopeTimeOffsetEffect>();
  constexpr int kEarth = GyroscopeEffectFirstOf<GyroscopeEarthRateEffect>();
  GyroscopeEffectCoefficients values{};
  values[kEarth] = 5e-5;
  GyroscopeCalibrationSection section;
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Identity(13, 13) * 1e-12;
  covariance.topLeftCorner(12, 12) = testing::ExampleGyroscopeCovariance();
  EXPECT_ERROR_CONTAINS(
      MakeGyroscopeCalibrationSection(testing::ExampleGyroscopeParameters(),
                                      testing::ExampleGyroscopeOffset(), {kEarth}, values,
                                      covariance, GyroscopeOutputUnit::kCount, &section),
      "gyroscope_earth_rate is not a term of the sensor's calibration");
  // A file edited to carry it in the time offset's place.
  CalibrationRecord record = testing::ExampleTriadRecord();
  values[kTimeOffset] = 3e-3;
  testing::AddExampleGyroscopeTerms({0, kTimeOffset}, values, {1e-12, 1e-8}, &record);
  nlohmann::json json = nlohmann::json::parse(Written(record));
  CalibrationRecord read;
  ASSERT_TRUE(Parsed(json, &read).ok());
  nlohmann::json& order = json["gyroscope"]["parameter_order"];
  ASSERT_EQ(order[13], "gyroscope_time_offset");
  order[13] = "gyroscope_earth_rate";
  json["gyroscope"]["parameters"]["gyroscope_earth_rate"] =
      json["gyroscope"]["parameters"]["gyroscope_time_offset"];
  json["gyroscope"]["parameters"].erase("gyroscope_time_offset");
  EXPECT_ERROR_CONTAINS(Parsed(json, &read),
                        "gyroscope/parameter_order[13] = \"gyroscope_earth_rate\": a calibration "
                        "carries the sensor's terms");
}

}  // namespace
}  // namespace accelcal
