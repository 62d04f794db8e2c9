// The calibration file (io/calibration_file.h): written and read back unchanged, its
// gyroscope section too, refused in one line when it does not say what it claims; and the
// correction apply makes with it (estimation/tilt_table/calibration_correction.h): the inverse of
// the model, with a sigma that matches the spread of corrections made with calibrations from
// independent tilt tests.

#include "io/calibration_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "estimation/tilt_table/calibration_correction.h"
#include "estimation/tilt_table/linear_ls.h"
#include "gyroscope_calibration_example.h"
#include "io/json_file.h"
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

// Issue 44, item 6: the gyroscope section's poorly determined unknowns round-trip as the
// accelerometer's do; a section without the key is read as not assessed; an entry naming no
// unknown of the section (an accelerometer parameter included) is refused, naming the key.
TEST(GyroscopeCalibrationSection, PoorlyDeterminedRoundTripsAndIsOptional) {
  CalibrationRecord written = testing::ExampleTriadRecordWithGyroscope();
  written.gyroscope.poorly_determined =
      nlohmann::json::array({{{"parameter", "gyroscope_misalignment_zy"},
                              {"reason", "sigma 0.0013 > 0.001 (0.001 rad)"},
                              {"sigma", 0.0013},
                              {"threshold", 0.001},
                              {"sigma_over_threshold", true},
                              {"correlated_with", nlohmann::json::array()},
                              {"suggestion", "turns about the sensor's z axis"}}});
  const nlohmann::json json = CalibrationJson(written);
  EXPECT_EQ(json["gyroscope"]["poorly_determined"], written.gyroscope.poorly_determined);
  CalibrationRecord read;
  Status status = ParseCalibration(json.dump(2), "cal.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(read.gyroscope.poorly_determined, written.gyroscope.poorly_determined);

  nlohmann::json without = json;
  without["gyroscope"].erase("poorly_determined");
  status = ParseCalibration(without.dump(), "cal.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_TRUE(read.gyroscope.poorly_determined.is_null());

  for (const nlohmann::json& bad :
       {nlohmann::json("gyroscope_gain_x"), nlohmann::json::array({{{"parameter", "gain_x"}}}),
        nlohmann::json::array({{{"reason", "no name"}}})}) {
    nlohmann::json damaged = json;
    damaged["gyroscope"]["poorly_determined"] = bad;
    status = ParseCalibration(damaged.dump(), "cal.json", &read);
    ASSERT_FALSE(status.ok()) << bad.dump();
    EXPECT_EQ(status.message().rfind("cal.json: ", 0), 0u) << status.message();
    EXPECT_NE(status.message().find("gyroscope/poorly_determined"), std::string::npos)
        << status.message();
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
      {"/format_version", 3, "format_version 3, but this accelcal reads versions 1 and 2; update"},
      {"/format_version", 2, "format_version 2 is written for a model with effect terms"},
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

// A stddev is the square root of its variance: one that is not was edited, and which of the
// two is right cannot be told. A hand-written file without stddev is still read.
TEST(CalibrationFile, RefusesAStddevThatContradictsTheCovariance) {
  const nlohmann::json good = CalibrationJson(ExampleRecord());
  CalibrationRecord record;
  nlohmann::json damaged = good;
  damaged["stddev"]["scale_x"] = 1.000002 * std::sqrt(2.6e-7);
  EXPECT_ERROR_CONTAINS(ParseCalibration(damaged.dump(), "cal.json", &record),
                        "cal.json: stddev/scale_x = ");
  EXPECT_ERROR_CONTAINS(ParseCalibration(damaged.dump(), "cal.json", &record),
                        "contradicts covariance[1][1] = 2.6e-07");
  damaged["stddev"]["scale_x"] = 1.0000005 * std::sqrt(2.6e-7);  // within 1e-6
  Status status = ParseCalibration(damaged.dump(), "cal.json", &record);
  EXPECT_TRUE(status.ok()) << status.message();
  damaged = good;
  damaged["stddev"]["scale_z"] = 0.1;
  EXPECT_ERROR_CONTAINS(ParseCalibration(damaged.dump(), "cal.json", &record),
                        "cal.json: stddev/scale_z: not a parameter of geometry two_axis");
  damaged = good;
  damaged["parameters"]["scale_z"] = 0.1;
  EXPECT_ERROR_CONTAINS(ParseCalibration(damaged.dump(), "cal.json", &record),
                        "cal.json: parameters/scale_z: not a parameter of geometry two_axis");
  damaged = good;
  damaged.erase("stddev");
  status = ParseCalibration(damaged.dump(), "cal.json", &record);
  EXPECT_TRUE(status.ok()) << status.message();
}

// The model's words are the format version's for the geometry (issue 35, 2): a file whose
// model.measurement, correction, axes or effects say another model was written for another
// model, and its parameters do not mean what this reader takes them for. A file without them
// (hand-written) is read; the gyroscope's measurement must at least be its equation.
TEST(CalibrationFile, RefusesAModelTextThatIsNotTheVersionsForItsGeometry) {
  const nlohmann::json good = CalibrationJson(ExampleRecord());
  CalibrationRecord record;
  struct Damage {
    const char* pointer;
    nlohmann::json value;
  };
  const Damage damages[] = {
      {"/model/measurement", "m_k = scale_k a_k + bias_k + noise_k, k = x, y"},
      {"/model/correction", "a_k = m_k / (1 + scale_k) - bias_k"},
      {"/model/axes", nlohmann::json::array({"x", "z"})},
      {"/model/effects", nlohmann::json::array({"bias", "scale", "angle_offset"})},
  };
  for (const Damage& damage : damages) {
    SCOPED_TRACE(damage.pointer);
    nlohmann::json damaged = good;
    damaged[nlohmann::json::json_pointer(damage.pointer)] = damage.value;
    const std::string key = std::string(damage.pointer).substr(1);
    EXPECT_ERROR_CONTAINS(ParseCalibration(damaged.dump(), "cal.json", &record),
                          "cal.json: " + key + " is ");
    EXPECT_ERROR_CONTAINS(ParseCalibration(damaged.dump(), "cal.json", &record),
                          "but format_version 1 writes ");
  }
  nlohmann::json hand_written = good;
  for (const char* key : {"measurement", "correction", "axes", "effects", "conventions"})
    hand_written["model"].erase(key);
  const Status status = ParseCalibration(hand_written.dump(), "cal.json", &record);
  EXPECT_TRUE(status.ok()) << status.message();

  nlohmann::json triad = CalibrationJson(testing::ExampleTriadRecordWithGyroscope());
  triad["gyroscope"]["model"]["measurement"] = "w = K (u - b)";
  EXPECT_ERROR_CONTAINS(
      ParseCalibration(triad.dump(), "cal.json", &record),
      "cal.json: gyroscope/model/measurement is \"w = K (u - b)\", but format_version "
      "1 writes \"w = T K (u - b)");
  triad["gyroscope"]["model"]["measurement"] = "w = T K (u - b)";  // the equation alone
  const Status short_form = ParseCalibration(triad.dump(), "cal.json", &record);
  EXPECT_TRUE(short_form.ok()) << short_form.message();
}

// nlohmann::json copies a document by recursion: a file nested a hundred thousand deep would
// overflow the stack in the first copy. The parser stops at kMaxJsonDepth and says where.
TEST(CalibrationFile, RefusesJsonNestedTooDeepInOneLine) {
  nlohmann::json json = CalibrationJson(testing::ExampleTriadRecordWithGyroscope());
  json["gyroscope"]["fit"] = "NESTED";
  const std::string text = json.dump();
  const size_t at = text.find("\"NESTED\"");
  ASSERT_NE(at, std::string::npos);
  CalibrationRecord record;
  for (const int depth : {100000, kMaxJsonDepth - 1, kMaxJsonDepth - 2}) {
    SCOPED_TRACE(depth);
    const std::string nested = text.substr(0, at) + std::string(depth, '[') +
                               std::string(depth, ']') + text.substr(at + 8);
    const Status status = ParseCalibration(nested, "cal.json", &record);
    if (depth > kMaxJsonDepth - 2) {
      EXPECT_ERROR_CONTAINS(status,
                            "cal.json: arrays and objects nested more than 64 deep, "
                            "under /gyroscope");
    } else {
      // The root and the gyroscope object are two levels: 62 more reach 64, and are refused as
      // a fit that is not an object, not as too deep.
      EXPECT_ERROR_CONTAINS(status, "cal.json: gyroscope/fit must be an object");
    }
  }
}

// The gyroscope's section: written and read back to the last bit, with the names, units and
// model a reader needs; a file without it (null, or written before the key) has none.
TEST(GyroscopeCalibrationSection, ReadsBackWhatItWroteToTheLastBit) {
  const CalibrationRecord written = testing::ExampleTriadRecordWithGyroscope();
  const nlohmann::json json = CalibrationJson(written);
  const nlohmann::json& section = json["gyroscope"];
  EXPECT_EQ(section["output_unit"], "count");
  ASSERT_EQ(section["parameter_order"].size(), 12u);
  EXPECT_EQ(section["parameter_order"][0], "gyroscope_misalignment_yz");
  EXPECT_EQ(section["parameter_order"][8], "gyroscope_gain_z");
  EXPECT_EQ(section["parameter_order"][9], "gyroscope_offset_x");
  EXPECT_EQ(section["parameter_order"][11], "gyroscope_offset_z");
  EXPECT_EQ(section["units"]["gyroscope_misalignment_xy"], "rad");
  EXPECT_EQ(section["units"]["gyroscope_gain_y"], "(rad/s)/count");
  EXPECT_EQ(section["units"]["gyroscope_offset_y"], "count");
  EXPECT_EQ(section["parameters"]["gyroscope_offset_y"], -12.25);
  EXPECT_EQ(section["stddev"]["gyroscope_offset_z"], 2.0);
  EXPECT_EQ(section["covariance"].size(), 12u);
  EXPECT_EQ(section["fit"]["turns"], 37);
  EXPECT_EQ(section["model"]["measurement"].get<std::string>().rfind("w = T K (u - b)", 0), 0u);
  EXPECT_NE(section["model"]["conventions"].get<std::string>().find("rad/s in the "
                                                                    "accelerometer's frame"),
            std::string::npos);

  CalibrationRecord read;
  Status status = ParseCalibration(json.dump(2), "cal.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_TRUE(read.has_gyroscope);
  EXPECT_EQ(read.gyroscope.output_unit, "count");
  EXPECT_EQ(read.gyroscope.parameter_order, written.gyroscope.parameter_order);
  EXPECT_EQ(read.gyroscope.values, written.gyroscope.values);
  EXPECT_EQ(read.gyroscope.covariance, written.gyroscope.covariance);
  EXPECT_EQ(read.gyroscope.fit, written.gyroscope.fit);
  EXPECT_EQ(read.values, written.values);
  GyroscopeParameters parameters;
  GyroscopeOffset offset;
  Eigen::MatrixXd covariance;
  GyroscopeOutputUnit unit;
  ASSERT_TRUE(GyroscopeCalibration(read.gyroscope, &parameters, &offset, &covariance, &unit).ok());
  EXPECT_EQ(parameters, testing::ExampleGyroscopeParameters());
  EXPECT_EQ(offset, testing::ExampleGyroscopeOffset());
  EXPECT_EQ(covariance, testing::ExampleGyroscopeCovariance());
  EXPECT_EQ(unit, GyroscopeOutputUnit::kCount);

  // In deg/s the gains' and offsets' units follow.
  CalibrationRecord in_degrees = testing::ExampleTriadRecord();
  GyroscopeParameters degree_gains = testing::ExampleGyroscopeParameters();
  for (int k = 0; k < 3; ++k) degree_gains[kGyroscopeGainX + k] = (1.0 + 0.01 * k) * M_PI / 180;
  Eigen::MatrixXd degree_covariance = testing::ExampleGyroscopeCovariance();
  for (int k = 0; k < 3; ++k) {
    const int p = kGyroscopeGainX + k;
    degree_covariance.row(p) *= 6258.0 * M_PI / 180;
    degree_covariance.col(p) *= 6258.0 * M_PI / 180;
  }
  status = MakeGyroscopeCalibrationSection(degree_gains, {0.5, -0.25, 0.1}, degree_covariance,
                                           GyroscopeOutputUnit::kDegPerS, &in_degrees.gyroscope);
  ASSERT_TRUE(status.ok()) << status.message();
  in_degrees.has_gyroscope = true;
  const nlohmann::json degrees = CalibrationJson(in_degrees);
  EXPECT_EQ(degrees["gyroscope"]["units"]["gyroscope_gain_x"], "(rad/s)/(deg/s)");
  EXPECT_EQ(degrees["gyroscope"]["units"]["gyroscope_offset_x"], "deg/s");
  status = ParseCalibration(degrees.dump(), "cal.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(read.gyroscope.output_unit, "deg/s");

  // None: null, or no key at all (a file of version 1 written before the section).
  const nlohmann::json none = CalibrationJson(testing::ExampleTriadRecord());
  EXPECT_TRUE(none.contains("gyroscope") && none["gyroscope"].is_null());
  status = ParseCalibration(none.dump(), "cal.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_FALSE(read.has_gyroscope);
  nlohmann::json before = none;
  before.erase("gyroscope");
  status = ParseCalibration(before.dump(), "cal.json", &read);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_FALSE(read.has_gyroscope);
  EXPECT_TRUE(CalibrationJson(ExampleRecord())["gyroscope"].is_null());
}

// Each damage of the section is refused in one line naming the file and the key.
TEST(GyroscopeCalibrationSection, RefusesWhatDoesNotSayWhatItClaims) {
  const nlohmann::json good = CalibrationJson(testing::ExampleTriadRecordWithGyroscope());
  const double gain_z_variance = good["gyroscope"]["covariance"][8][8].get<double>();
  const double c = 2.0 * std::sqrt(good["gyroscope"]["covariance"][0][0].get<double>() *
                                   good["gyroscope"]["covariance"][1][1].get<double>());
  struct Damage {
    const char* what;
    std::function<void(nlohmann::json*)> damage;
    const char* expected;
  };
  using Json = nlohmann::json;
  const Damage damages[] = {
      {"missing parameter",
       [](Json* j) { (*j)["gyroscope"]["parameters"].erase("gyroscope_gain_y"); },
       "the key \"gyroscope/parameters/gyroscope_gain_y\" is missing"},
      {"unknown parameter",
       [](Json* j) { (*j)["gyroscope"]["parameters"]["gyroscope_gain_w"] = 1; },
       "gyroscope/parameters/gyroscope_gain_w: not a parameter of the gyroscope section"},
      {"parameter order",
       [](Json* j) { (*j)["gyroscope"]["parameter_order"][9] = "gyroscope_offset_y"; },
       "gyroscope/parameter_order must be [gyroscope_misalignment_yz, "},
      {"wrong gain unit",
       [](Json* j) { (*j)["gyroscope"]["units"]["gyroscope_gain_x"] = "(rad/s)/(deg/s)"; },
       "gyroscope/units/gyroscope_gain_x must be \"(rad/s)/count\""},
      {"wrong offset unit",
       [](Json* j) { (*j)["gyroscope"]["units"]["gyroscope_offset_z"] = "deg/s"; },
       "gyroscope/units/gyroscope_offset_z must be \"count\""},
      {"relabelled output unit", [](Json* j) { (*j)["gyroscope"]["output_unit"] = "deg/s"; },
       "gyroscope/units/gyroscope_gain_x must be \"(rad/s)/(deg/s)\""},
      {"unknown output unit", [](Json* j) { (*j)["gyroscope"]["output_unit"] = "rpm"; },
       "gyroscope/output_unit: 'rpm' is not a gyroscope unit"},
      {"no output unit", [](Json* j) { (*j)["gyroscope"].erase("output_unit"); },
       "the key \"gyroscope/output_unit\" is missing"},
      {"asymmetric covariance", [](Json* j) { (*j)["gyroscope"]["covariance"][3][5] = 1e-7; },
       "gyroscope/covariance is not symmetric (gyroscope_misalignment_yx, "
       "gyroscope_misalignment_xz)"},
      {"not positive semi-definite",
       [c](Json* j) {
         (*j)["gyroscope"]["covariance"][0][1] = c;
         (*j)["gyroscope"]["covariance"][1][0] = c;
       },
       "gyroscope/covariance is not positive semi-definite"},
      {"negative variance", [](Json* j) { (*j)["gyroscope"]["covariance"][10][10] = -4.0; },
       "gyroscope/covariance: the variance of gyroscope_offset_y is not positive"},
      {"covariance 11x11", [](Json* j) { (*j)["gyroscope"]["covariance"].erase(11); },
       "gyroscope/covariance must be a 12x12 array of arrays"},
      {"stddev contradicting the covariance",
       [gain_z_variance](Json* j) {
         (*j)["gyroscope"]["stddev"]["gyroscope_gain_z"] = 2.0 * std::sqrt(gain_z_variance);
       },
       "gyroscope/stddev/gyroscope_gain_z = "},
      {"stddev contradicting the covariance, both named",
       [gain_z_variance](Json* j) {
         (*j)["gyroscope"]["stddev"]["gyroscope_gain_z"] = 2.0 * std::sqrt(gain_z_variance);
       },
       "contradicts gyroscope/covariance[8][8] = "},
      {"no stddev", [](Json* j) { (*j)["gyroscope"].erase("stddev"); },
       "gyroscope/stddev must be an object"},
      {"NaN parameter (written as null)",
       [](Json* j) { (*j)["gyroscope"]["parameters"]["gyroscope_offset_x"] = std::nan(""); },
       "gyroscope/parameters/gyroscope_offset_x must be a number"},
      {"NaN covariance (written as null)",
       [](Json* j) { (*j)["gyroscope"]["covariance"][4][3] = std::nan(""); },
       "gyroscope/covariance[4][3] is not a finite number"},
      {"NaN stddev (written as null)",
       [](Json* j) { (*j)["gyroscope"]["stddev"]["gyroscope_gain_x"] = std::nan(""); },
       "gyroscope/stddev/gyroscope_gain_x must be a finite number"},
      {"negative gain",
       [](Json* j) { (*j)["gyroscope"]["parameters"]["gyroscope_gain_x"] = -1e-4; },
       "gyroscope/parameters/gyroscope_gain_x is not positive"},
      {"gains of a log in rad/s, said counts",
       [](Json* j) {
         for (const char* axis : {"x", "y", "z"}) {
           (*j)["gyroscope"]["parameters"][std::string("gyroscope_gain_") + axis] = 1.0;
         }
       },
       "gyroscope/parameters: the gyroscope's gain_z came out 1 (rad/s) per count, as a "
       "gyroscope in rad/s would"},
      {"not an object", [](Json* j) { (*j)["gyroscope"] = "yes"; },
       "\"gyroscope\" must be an object (the gyroscope's calibration) or null"},
      {"fit not an object", [](Json* j) { (*j)["gyroscope"]["fit"] = Json::array({1}); },
       "gyroscope/fit must be an object"},
  };
  for (const Damage& damage : damages) {
    SCOPED_TRACE(damage.what);
    nlohmann::json damaged = good;
    damage.damage(&damaged);
    CalibrationRecord record;
    const Status status = ParseCalibration(damaged.dump(), "cal.json", &record);
    EXPECT_ERROR_CONTAINS(status, damage.expected);
    EXPECT_EQ(status.message().rfind("cal.json: ", 0), 0u) << status.message();
  }
  // A value beyond a double, as text: no infinity gets in.
  CalibrationRecord record;
  std::string infinite = good.dump();
  const std::string matrix = "\"covariance\":[[";
  const size_t open = infinite.find(matrix, infinite.find("\"gyroscope\":"));
  ASSERT_NE(open, std::string::npos);
  const size_t first = open + matrix.size();
  infinite.replace(first, infinite.find(',', first) - first, "1e999");
  EXPECT_ERROR_CONTAINS(ParseCalibration(infinite, "cal.json", &record),
                        "cal.json: not valid JSON ([json.exception.out_of_range.406] number "
                        "overflow parsing '1e999')");
  // A two-axis file has no gyroscope.
  nlohmann::json two_axis = CalibrationJson(ExampleRecord());
  two_axis["gyroscope"] = good["gyroscope"];
  EXPECT_ERROR_CONTAINS(ParseCalibration(two_axis.dump(), "cal.json", &record),
                        "cal.json: \"gyroscope\": a gyroscope's calibration belongs to a triad's "
                        "file; this one's geometry is two_axis");
}

// The writer's helper refuses what the reader would, so that a file written is a file read.
TEST(GyroscopeCalibrationSection, MakeRefusesWhatTheReaderWould) {
  GyroscopeCalibrationSection section;
  const GyroscopeParameters parameters = testing::ExampleGyroscopeParameters();
  const GyroscopeOffset offset = testing::ExampleGyroscopeOffset();
  const Eigen::MatrixXd covariance = testing::ExampleGyroscopeCovariance();
  EXPECT_ERROR_CONTAINS(
      MakeGyroscopeCalibrationSection(parameters, offset, covariance.topLeftCorner(9, 9),
                                      GyroscopeOutputUnit::kCount, &section),
      "gyroscope/covariance is 9x9, not 12x12");
  Eigen::MatrixXd singular = covariance;
  singular.row(9).setZero();
  singular.col(9).setZero();
  EXPECT_ERROR_CONTAINS(MakeGyroscopeCalibrationSection(parameters, offset, singular,
                                                        GyroscopeOutputUnit::kCount, &section),
                        "gyroscope/covariance: the variance of gyroscope_offset_x is not positive");
  Eigen::MatrixXd not_finite = covariance;
  not_finite(2, 3) = std::nan("");
  EXPECT_ERROR_CONTAINS(MakeGyroscopeCalibrationSection(parameters, offset, not_finite,
                                                        GyroscopeOutputUnit::kCount, &section),
                        "gyroscope/covariance is not finite");
  GyroscopeOffset nan_offset = offset;
  nan_offset[1] = std::nan("");
  EXPECT_ERROR_CONTAINS(MakeGyroscopeCalibrationSection(parameters, nan_offset, covariance,
                                                        GyroscopeOutputUnit::kCount, &section),
                        "gyroscope/parameters/gyroscope_offset_y = nan is not a finite number");
  EXPECT_ERROR_CONTAINS(MakeGyroscopeCalibrationSection(parameters, offset, covariance,
                                                        GyroscopeOutputUnit::kRadPerS, &section),
                        "gyroscope/parameters: the gyroscope's output at rest averages 31.5 rad/s "
                        "on its x axis");
  EXPECT_TRUE(section.parameter_order.empty());  // untouched by a refusal
}

// apply's correction of a gyroscope sample: the model's w = T K (u - b) and J C J^T, against
// the matrices written out and J by central differences (tests/test_support.h).
TEST(CorrectGyroscope, IsTheModelWithTheCovarianceOfItsParameters) {
  const GyroscopeParameters parameters = testing::ExampleGyroscopeParameters();
  const GyroscopeOffset offset = testing::ExampleGyroscopeOffset();
  const Eigen::MatrixXd covariance = testing::ExampleGyroscopeCovariance();
  Eigen::VectorXd values(kGyroscopeCalibrationParameterCount);
  for (int p = 0; p < kGyroscopeParameterCount; ++p) values[p] = parameters[p];
  for (int k = 0; k < 3; ++k) values[kGyroscopeCalibrationOffsetX + k] = offset[k];
  for (const std::array<double, 3>& raw : std::vector<std::array<double, 3>>{
           {31.5, -12.25, 7.0}, {6290.0, -12.0, 9.5}, {-3000.25, 12000.0, -8000.5}}) {
    SCOPED_TRACE(raw[0]);
    const CorrectedGyroscopeSample sample = CorrectGyroscope(parameters, offset, covariance, raw);
    const Eigen::Vector3d u(raw[0], raw[1], raw[2]);
    EXPECT_EIGEN_NEAR(sample.angular_rate, testing::PlainGyroscopeRate(values, u), 1e-12);
    const Eigen::Matrix3d expected = testing::PlainGyroscopeRateCovariance(values, covariance, u);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        EXPECT_NEAR(sample.covariance(i, j), expected(i, j),
                    1e-9 * std::sqrt(expected(i, i) * expected(j, j)))
            << i << ", " << j;
      }
    }
  }
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
