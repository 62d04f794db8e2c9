// The reader of imucal's annotated Ferraris session and of its calibration JSON, and the
// ferraris mode's report (its text and JSON).

#include "common/ferraris_session.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "common/format.h"
#include "io/imucal_calibration_json.h"
#include "io/imucal_session.h"
#include "io/json_file.h"
#include "reporting/ferraris_report.h"
#include "test_support.h"

namespace accelcal {
namespace {

constexpr char kHeader[] = "part,samples,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z\n";

// Two rows per section, labels in imucal's order, values that identify the section.
std::string SmallSession() {
  std::string text = kHeader;
  int sample = 0;
  for (int s = 0; s < kFerrarisSectionCount; ++s) {
    for (int row = 0; row < 2; ++row) {
      text += StringPrintf("%s,%d,%d,%d,%d,%d,%d,%d\n", kFerrarisSectionLabels[s], sample++,
                           100 * s + row, -s, 32768 + 2 * row, s, 0, -row);
    }
  }
  return text;
}

TEST(ImucalSession, ReadsEveryRowOfImucalsExample) {
  ACCELCAL_REQUIRE_IMUCAL_DATA(dir);
  FerrarisSession session;
  const Status status = ReadImucalSession(dir + "/annotated_session.csv", &session);
  ASSERT_TRUE(status.ok()) << status.message();
  // Rows per label, as `cut -d, -f1 | uniq -c` counts them.
  const int expected[kFerrarisSectionCount] = {1028, 1061, 734, 848, 881, 1044, 1305, 1093, 1420};
  int rows = 0;
  for (int s = 0; s < kFerrarisSectionCount; ++s) {
    EXPECT_EQ(session.sections[s].accelerometer.sample_count, expected[s])
        << kFerrarisSectionLabels[s];
    rows += expected[s];
  }
  EXPECT_EQ(rows, 9414);
  // The file starts with x_a (line 2 after the header).
  EXPECT_EQ(session[kXa].first_line, 2);
  EXPECT_EQ(session[kXa].last_line, 1062);
}

TEST(ImucalSession, KeepsEachSectionsMeanAndSampleVariance) {
  FerrarisSession session;
  ASSERT_TRUE(ParseImucalSession(SmallSession(), &session).ok());
  for (int s = 0; s < kFerrarisSectionCount; ++s) {
    const FerrarisSectionData& section = session.sections[s];
    EXPECT_EQ(section.accelerometer.sample_count, 2);
    EXPECT_DOUBLE_EQ(section.accelerometer.mean[0], 100 * s + 0.5);
    EXPECT_DOUBLE_EQ(section.accelerometer.mean[1], -s);
    EXPECT_DOUBLE_EQ(section.accelerometer.mean[2], 32769.0);
    // Two values d apart have sample variance d^2 / 2.
    EXPECT_DOUBLE_EQ(section.accelerometer.variance[0], 0.5);
    EXPECT_DOUBLE_EQ(section.accelerometer.variance[1], 0.0);
    EXPECT_DOUBLE_EQ(section.accelerometer.variance[2], 2.0);
    EXPECT_DOUBLE_EQ(section.gyroscope.mean[0], s);
    EXPECT_DOUBLE_EQ(section.gyroscope.mean[2], -0.5);
    EXPECT_DOUBLE_EQ(section.gyroscope.variance[2], 0.5);
    EXPECT_EQ(section.first_line, 2 + 2 * s);
  }
}

TEST(ImucalSession, GathersASectionsRowsWhereverTheyAre) {
  std::string text = SmallSession();
  text += "x_p,99,300,0,32768,0,0,0\n";  // a third x_p row at the end, as imucal's groupby
  FerrarisSession session;
  ASSERT_TRUE(ParseImucalSession(text, &session).ok());
  EXPECT_EQ(session[kXp].accelerometer.sample_count, 3);
  EXPECT_DOUBLE_EQ(session[kXp].accelerometer.mean[0], 301.0 / 3.0);
}

TEST(ImucalSession, RefusesAMissingSection) {
  std::string text = kHeader;
  for (int s = 0; s < kFerrarisSectionCount - 1; ++s)
    text += std::string(kFerrarisSectionLabels[s]) + ",0,1,2,3,4,5,6\n";
  FerrarisSession session;
  EXPECT_ERROR_CONTAINS(ParseImucalSession(text, &session),
                        "no row is labelled 'z_rot': a Ferraris session needs all nine sections");
}

TEST(ImucalSession, RefusesAnUnknownOrEmptyLabelWithItsLine) {
  FerrarisSession session;
  EXPECT_ERROR_CONTAINS(ParseImucalSession(SmallSession() + "x_up,1,1,2,3,4,5,6\n", &session),
                        "line 20, column 'part': 'x_up' is not a section of a Ferraris session");
  EXPECT_ERROR_CONTAINS(ParseImucalSession(SmallSession() + ",1,1,2,3,4,5,6\n", &session),
                        "line 20, column 'part': the cell is empty");
}

TEST(ImucalSession, RefusesAValueThatIsNotANumber) {
  FerrarisSession session;
  EXPECT_ERROR_CONTAINS(ParseImucalSession(SmallSession() + "x_p,1,1,2,3,4,five,6\n", &session),
                        "line 20, column 'gyr_y': 'five' is not a number");
  EXPECT_ERROR_CONTAINS(ParseImucalSession(SmallSession() + "x_p,1,1,nan,3,4,5,6\n", &session),
                        "line 20, column 'acc_y': 'nan' is not a finite number");
}

TEST(ImucalSession, RefusesAWrongHeaderAndAFileCutShort) {
  FerrarisSession session;
  EXPECT_ERROR_CONTAINS(
      ParseImucalSession("n_samples,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z\n1,2,3,4,5,6,7\n",
                         &session),
      "expected 'part,samples,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z'");
  EXPECT_ERROR_CONTAINS(ParseImucalSession(SmallSession() + "x_p,1,1,2", &session),
                        "line 20 has no line end");
}

TEST(ImucalSession, NamesTheFileWhenReadingFromDisk) {
  testing::ScratchDir dir;
  const std::string path = dir.Write("session.csv", SmallSession() + "x_p,1,1,2,3,4,five,6\n");
  FerrarisSession session;
  const Status status = ReadImucalSession(path, &session);
  EXPECT_EQ(status.message().rfind(path + ": line 20, column 'gyr_y'", 0), 0u) << status.message();
  const std::string good = dir.Write("good.csv", SmallSession());
  FerrarisSession streamed;
  FerrarisSession parsed;
  ASSERT_TRUE(ReadImucalSession(good, &streamed).ok());
  ASSERT_TRUE(ParseImucalSession(SmallSession(), &parsed).ok());
  for (int s = 0; s < kFerrarisSectionCount; ++s)
    EXPECT_EQ(streamed.sections[s].accelerometer.mean, parsed.sections[s].accelerometer.mean);
  EXPECT_ERROR_CONTAINS(ReadImucalSession(dir.File("absent.csv"), &session),
                        dir.File("absent.csv") + ": no such file");
}

TEST(ImucalSession, ReadsImucalsCalibrationJson) {
  ACCELCAL_REQUIRE_IMUCAL_DATA(dir);
  ImucalCalibration calibration;
  const Status status = ReadImucalCalibrationJson(dir + "/example_cal.json", &calibration);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_TRUE(calibration.has_gyroscope);
  // Figures as the file writes them.
  EXPECT_EQ(calibration.accelerometer.k_a(0, 0), 208.54567263762615);
  EXPECT_EQ(calibration.accelerometer.r_a(2, 1), -0.010781879507682177);
  EXPECT_EQ(calibration.accelerometer.b_a[1], -48.287874016760156);
  EXPECT_EQ(calibration.gyroscope.k_ga(0, 2), 0.018465435717563698);
  EXPECT_EQ(calibration.gyroscope.b_g[2], -3.6511794138670477);
}

TEST(ImucalSession, RefusesACalibrationJsonOfTheWrongShape) {
  ImucalCalibration calibration;
  const std::string identity = "[[1,0,0],[0,1,0],[0,0,1]]";
  EXPECT_ERROR_CONTAINS(ParseImucalCalibrationJson("{\"K_a\": " + identity + "}", &calibration),
                        "no key \"R_a\"");
  EXPECT_ERROR_CONTAINS(
      ParseImucalCalibrationJson(
          "{\"K_a\": " + identity + ", \"R_a\": [[1,0],[0,1]], \"b_a\": [0,0,0]}", &calibration),
      "R_a must be a 3x3 array");
  EXPECT_ERROR_CONTAINS(
      ParseImucalCalibrationJson("{\"K_a\": " + identity + ", \"R_a\": " + identity +
                                     ", \"b_a\": [0,\"x\",0], \"K_g\": " + identity + "}",
                                 &calibration),
      "b_a[1] is \"x\", not a finite number");
  EXPECT_ERROR_CONTAINS(
      ParseImucalCalibrationJson("{\"K_a\": " + identity + ", \"R_a\": " + identity +
                                     ", \"b_a\": [0,0,0], \"K_g\": " + identity + "}",
                                 &calibration),
      "the gyroscope is given in part");
}

// ---- The report.

class FerrarisReportOnImucalsExample : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string dir = testing::ImucalDataDir();
    if (dir.empty()) GTEST_SKIP() << "imucal data not found: set ACCELCAL_IMUCAL_DATA";
    report_.session_path = dir + "/annotated_session.csv";
    ASSERT_TRUE(ReadImucalSession(report_.session_path, &report_.session).ok());
    report_.options.sampling_rate_hz = 204.8;
    const Status analysed = AnalyzeFerraris(report_.session, report_.options,
                                            FerrarisLeastSquaresOptions(), &report_.analysis);
    ASSERT_TRUE(analysed.ok()) << analysed.message();
    report_.reference_path = dir + "/example_cal.json";
    report_.has_reference = true;
    ASSERT_TRUE(ReadImucalCalibrationJson(report_.reference_path, &report_.reference).ok());
  }
  FerrarisReport report_;
};

TEST_F(FerrarisReportOnImucalsExample, JsonHasEveryKeyTheModeDocuments) {
  const nlohmann::json json = FerrarisJson(report_);
  EXPECT_EQ(FirstNonFiniteNumber(json), "");
  EXPECT_EQ(json.at("mode"), "ferraris");
  for (const char* key : {"parameters", "stddev", "units"}) {
    ASSERT_EQ(json.at(key).size(), 9u) << key;
    for (const TriadParameterInfo& info : TriadParameterInfos())
      EXPECT_TRUE(json.at(key).contains(info.name)) << key << " " << info.name;
  }
  for (const char* key : {"K_a", "R_a", "b_a", "K_g", "R_g", "K_ga", "b_g"}) {
    EXPECT_TRUE(json.at("imucal").contains(key)) << key;
  }
  EXPECT_EQ(json.at("imucal").at("K_a").at(1).at(1).get<double>(), 208.0011341167055);
  EXPECT_LT(json.at("reference").at("max_relative_difference").get<double>(), 1e-12);
  EXPECT_EQ(json.at("not_identifiable"),
            (nlohmann::json{"misalignment_yz", "misalignment_zy", "misalignment_zx"}));
  EXPECT_EQ(json.at("identifiable").size(), 6u);
  EXPECT_EQ(json.at("dof"), 6);
  EXPECT_GT(json.at("chi2").get<double>(), 1e4);
  EXPECT_EQ(json.at("unknown_directions").at("stddev").at("misalignment_zx").get<double>(), 0.0);
  EXPECT_GT(json.at("unknown_directions").at("stddev").at("offset_z").get<double>(), 0.0);
}

TEST_F(FerrarisReportOnImucalsExample, TableShowsTheClosedFormBesideTheReference) {
  const std::string table = FerrarisTable(report_);
  EXPECT_NE(table.find(report_.reference_path), std::string::npos) << table;
  EXPECT_NE(table.find("208.545672638"), std::string::npos) << table;
  const std::string difference =
      "largest relative difference from the reference, element by element: ";
  const size_t at = table.find(difference);
  ASSERT_NE(at, std::string::npos) << table;
  EXPECT_LT(std::stod(table.substr(at + difference.size())), 1e-12) << table;
  EXPECT_NE(table.find("not identifiable (null-space weight): misalignment_yz 0.7"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("opposite holds are not antiparallel"), std::string::npos) << table;
  for (const char* not_finite : {" nan", "-nan", " inf", "-inf"})
    EXPECT_EQ(table.find(not_finite), std::string::npos) << table;
}

}  // namespace
}  // namespace accelcal
