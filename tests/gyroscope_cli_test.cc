// The whole IMU, start to finish (issue 32, 6): a simulated hand-held session written as the CSV
// a logger writes (t, ax, ay, az, gx, gy, gz in counts), calibrated by calibrate_imu --mode=ml
// (both sensors, the gyroscope's truth recovered within its sigma, its section in the calibration
// file equal to the JSON's), then corrected by apply (the gyroscope at rest reads zero within its
// noise); gyroscope_study's refusal of a design whose turns are all about one axis.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/format.h"
#include "gyroscope_one_axis_session.h"
#include "studies/gyroscope_monte_carlo.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::RunBinaryArgs;

// `log` as the CSV a logger writes: t, ax, ay, az, gx, gy, gz in counts.
void WriteCountsCsv(const TriadLog& log, const std::string& csv) {
  std::ofstream out(csv);
  out << "t,ax,ay,az,gx,gy,gz\n";
  for (size_t i = 0; i < log.size(); ++i) {
    out << StringPrintf("%.2f,%.0f,%.0f,%.0f,%.0f,%.0f,%.0f\n", log.timestamp_s[i],
                        log.output[i][0], log.output[i][1], log.output[i][2], log.gyroscope[i][0],
                        log.gyroscope[i][1], log.gyroscope[i][2]);
  }
}

// `log` written as `csv` and calibrated by calibrate_imu --mode=ml (gyroscope in counts, gains
// started at 2.1e-4 rad/s per count), its calibration file at `calibration`, its JSON in *json,
// the run in *run.
void CalibrateCountsCsv(const TriadLog& log, const std::string& csv, const std::string& calibration,
                        nlohmann::json* json, testing::CommandResult* run) {
  WriteCountsCsv(log, csv);
  const std::string json_path = csv + ".json";
  *run =
      RunBinaryArgs("calibrate_imu", {"--log=" + csv, "--mode=ml", "--g=9.81744",
                                      "--gyro_unit=count", "--initial_gyro_gain=0.00021",
                                      "--json=" + json_path, "--calibration_out=" + calibration});
  ASSERT_EQ(run->exit_status, 0) << run->stderr_text;
  *json = nlohmann::json::parse(testing::ReadText(json_path));
}

// apply's output: its header's columns and its rows (the '#' lines skipped).
void ReadCorrectedCsv(const std::string& path, std::vector<std::string>* header,
                      std::vector<std::vector<double>>* rows) {
  std::istringstream lines(testing::ReadText(path));
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
    if (header->empty()) {
      *header = fields;
      continue;
    }
    std::vector<double> row;
    for (const std::string& cell : fields) row.push_back(std::stod(cell));
    rows->push_back(row);
  }
}

// apply of `calibration` to `csv`, written to `corrected`, and its output read back.
void ApplyAndRead(const std::string& calibration, const std::string& csv,
                  const std::string& corrected, std::vector<std::string>* header,
                  std::vector<std::vector<double>>* rows) {
  const testing::CommandResult applied =
      RunBinaryArgs("apply", {"--calibration=" + calibration, "--in=" + csv, "--out=" + corrected});
  ASSERT_EQ(applied.exit_status, 0) << applied.stderr_text;
  ReadCorrectedCsv(corrected, header, rows);
}

TEST(GyroscopeCli, CalibratesASimulatedLogAndAppliesTheCalibrationToItsGyroscopeColumns) {
  GyroscopeSessionDesign design;
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 21);
  GyroscopeSessionFit fit;
  ASSERT_TRUE(SimulateAndCalibrateGyroscope(design, holds, 22, {}, &fit).ok());
  const TriadLog& log = fit.session.log;
  testing::ScratchDir scratch;
  const std::string csv = scratch.File("session.csv");
  const std::string calibration = scratch.File("calibration.json");
  nlohmann::json json;
  testing::CommandResult run;
  ASSERT_NO_FATAL_FAILURE(CalibrateCountsCsv(log, csv, calibration, &json, &run));
  const nlohmann::json& g = json.at("gyroscope");
  const nlohmann::json file = nlohmann::json::parse(testing::ReadText(calibration));
  const nlohmann::json& section = file.at("gyroscope");
  ASSERT_TRUE(section.is_object());
  std::vector<double> truth(design.truth.begin(), design.truth.end());
  truth.insert(truth.end(), design.offset.begin(), design.offset.end());
  const nlohmann::json& order = g.at("parameter_order");
  ASSERT_EQ(order.size(), 12u);
  for (size_t i = 0; i < order.size(); ++i) {
    const std::string name = order[i];
    const double value = g.at("parameters").at(name);
    const double sigma = g.at("stddev").at(name);
    EXPECT_LT(std::abs(value - truth[i]), 4.0 * sigma) << name << " " << value << " +- " << sigma;
    EXPECT_DOUBLE_EQ(section.at("parameters").at(name).get<double>(), value) << name;
    EXPECT_DOUBLE_EQ(section.at("stddev").at(name).get<double>(), sigma) << name;
  }
  // A well-spread session: nothing poorly determined, in the JSON and the file alike.
  EXPECT_EQ(g.at("poorly_determined"), nlohmann::json::array());
  EXPECT_EQ(section.at("poorly_determined"), nlohmann::json::array());
  EXPECT_NE(run.stdout_text.find("Poorly determined, gyroscope: none"), std::string::npos);

  // The corrected rates over the true holds: zero within the mean's noise (3 counts of
  // 2.1e-4 rad/s per sample, some 10^4 samples) and the offsets' sigma.
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  ASSERT_NO_FATAL_FAILURE(
      ApplyAndRead(calibration, csv, scratch.File("corrected.csv"), &header, &rows));
  ASSERT_EQ(rows.size(), log.size());
  const auto column = [&](const std::string& name) {
    return static_cast<int>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const int gx = column("gx_radps");
  const int sigma_gx = column("sigma_gx_radps");
  ASSERT_LT(sigma_gx, static_cast<int>(header.size()));
  for (int k = 0; k < 3; ++k) {
    double sum = 0.0;
    int count = 0;
    for (const TriadHoldSamples& hold : fit.session.holds) {
      for (int i = hold.start; i <= hold.end; ++i, ++count) sum += rows[i][gx + k];
    }
    EXPECT_LT(std::abs(sum / count), 1e-4) << "axis " << k;
    EXPECT_GT(rows[0][sigma_gx + k], 0.0);
  }
}

// The calibration is the model discovery settled on (issue 44, item 7): a simulated gyroscope
// with a g-sensitivity of 2e-4 (rad/s)/(m/s^2) on the diagonal and 1e-4 off it (2e-3 rad/s, 0.1
// deg/s, at 1 g: a common MEMS datasheet figure, eighty times a pose mean's noise). The
// 12-unknown baseline, which does not model it, once collapsed its gains towards 0 through the
// free vertical Earth rate and refused the session; its vertical rate is now held then. Discovery
// names it; the JSON, the table and the calibration file give the extended model (the 12 and the 9
// terms, truth within 4 sigma) with the 12 unknowns' fit beside it; apply applies the terms, so
// that the corrected rates at rest are zero within the noise, where the baseline's correction
// leaves G f in every pose; the imu_tk export writes the baseline and says so.
TEST(GyroscopeCli, WritesTheModelDiscoverySettledOnAndApplyAppliesItsTerms) {
  GyroscopeSessionDesign design;
  for (int c = 0; c < 9; ++c)
    design.effects[GyroscopeEffectFirstOf<GyroscopeGSensitivityEffect>() + c] =
        c % 4 == 0 ? 2e-4 : 1e-4;
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 31);
  GyroscopeSessionFit fit;
  ASSERT_TRUE(SimulateAndCalibrateGyroscope(design, holds, 32, {}, &fit).ok());
  testing::ScratchDir scratch;
  const std::string csv = scratch.File("session.csv");
  const std::string calibration = scratch.File("calibration.json");
  nlohmann::json json;
  testing::CommandResult run;
  ASSERT_NO_FATAL_FAILURE(CalibrateCountsCsv(fit.session.log, csv, calibration, &json, &run));
  const nlohmann::json& g = json.at("gyroscope");
  ASSERT_EQ(g.at("effect_terms").size(), 9u) << g.at("verdict_text");
  ASSERT_TRUE(g.at("baseline").is_object());
  EXPECT_NE(run.stdout_text.find("The model discovery settled on, its effect terms below the 12"),
            std::string::npos);
  std::vector<double> truth(design.truth.begin(), design.truth.end());
  truth.insert(truth.end(), design.offset.begin(), design.offset.end());
  for (int c = 0; c < 9; ++c)
    truth.push_back(design.effects[GyroscopeEffectFirstOf<GyroscopeGSensitivityEffect>() + c]);
  const nlohmann::json& order = g.at("parameter_order");
  ASSERT_EQ(order.size(), 21u);
  const nlohmann::json file = nlohmann::json::parse(testing::ReadText(calibration));
  EXPECT_EQ(file.at("format_version"), 2);
  const nlohmann::json& section = file.at("gyroscope");
  EXPECT_EQ(section.at("parameter_order"), order);
  for (size_t i = 0; i < order.size(); ++i) {
    const std::string name = order[i];
    const double value = g.at("parameters").at(name);
    const double sigma = g.at("stddev").at(name);
    EXPECT_LT(std::abs(value - truth[i]), 4.0 * sigma) << name << " " << value << " +- " << sigma;
    EXPECT_DOUBLE_EQ(section.at("parameters").at(name).get<double>(), value) << name;
  }
  EXPECT_EQ(section.at("baseline").at("parameters"), g.at("baseline").at("parameters"));

  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  ASSERT_NO_FATAL_FAILURE(
      ApplyAndRead(calibration, csv, scratch.File("corrected.csv"), &header, &rows));
  ASSERT_EQ(rows.size(), fit.session.log.size());
  const int gx =
      static_cast<int>(std::find(header.begin(), header.end(), "gx_radps") - header.begin());
  ASSERT_LT(gx, static_cast<int>(header.size()));
  // Each hold's mean rate, rms over holds and axes: the applied model's, and the baseline's
  // correction of the same samples.
  GyroscopeParameters baseline{};
  GyroscopeOffset baseline_offset{};
  for (int i = 0; i < 12; ++i) {
    const double value = g.at("baseline").at("parameters").at(order[i].get<std::string>());
    if (i < 9)
      baseline[i] = value;
    else
      baseline_offset[i - 9] = value;
  }
  double applied_sum = 0.0, baseline_sum = 0.0;
  int count = 0;
  for (const TriadHoldSamples& hold : fit.session.holds) {
    for (int k = 0; k < 3; ++k) {
      double mean = 0.0, mean_baseline = 0.0;
      for (int i = hold.start; i <= hold.end; ++i) {
        mean += rows[i][gx + k];
        double rate[3];
        GyroscopeAngularRate(baseline.data(), baseline_offset.data(),
                             fit.session.log.gyroscope[i].data(), rate);
        mean_baseline += rate[k];
      }
      const int n = hold.end - hold.start + 1;
      applied_sum += (mean / n) * (mean / n);
      baseline_sum += (mean_baseline / n) * (mean_baseline / n);
      ++count;
    }
  }
  const double applied_rms = std::sqrt(applied_sum / count);
  const double baseline_rms = std::sqrt(baseline_sum / count);
  // A hold's mean: 3 counts of 2.1e-4 rad/s over 400 samples, 3e-5 rad/s; G f: 2e-3 rad/s.
  EXPECT_LT(applied_rms, 1e-4);
  EXPECT_GT(baseline_rms, 5.0 * applied_rms);

  const testing::CommandResult exported = RunBinaryArgs(
      "export_calibration",
      {"--calibration=" + calibration, "--format=imu_tk", "--out=" + scratch.File("x")});
  ASSERT_EQ(exported.exit_status, 0) << exported.stderr_text;
  EXPECT_NE(exported.stdout_text.find("the gyroscope's effect terms"), std::string::npos);
  EXPECT_NE(exported.stdout_text.find("its 12 parameters are the baseline's"), std::string::npos);
}

// A session turned 85% about x (gyroscope_one_axis_session.h), with Xsens's 27 counts of
// gyroscope noise: the table, the JSON's gyroscope block, the calibration file's gyroscope section
// and the HTML report name misalignment_yz and _yx (turns about y) and _zy and _zx (turns about
// z), and the gyroscope's verdict says the session does not determine them.
TEST(GyroscopeCli, NamesTheUnknownsATurnedAboutOneAxisSessionLeavesPoorlyDetermined) {
  const GyroscopeSessionDesign design = testing::NoisyGyroscopeDesign();
  GyroscopeSessionFit fit;
  ASSERT_TRUE(
      SimulateAndCalibrateGyroscope(design, testing::MostlyAboutXHolds(design.hold_s), 3, {}, &fit)
          .ok());
  testing::ScratchDir scratch;
  const std::string csv = scratch.File("session.csv");
  WriteCountsCsv(fit.session.log, csv);
  const std::string json_path = scratch.File("out.json");
  const std::string calibration = scratch.File("calibration.json");
  const std::string report = scratch.File("report.html");
  const testing::CommandResult run = RunBinaryArgs(
      "calibrate_imu", {"--log=" + csv, "--mode=ml", "--g=9.81744", "--gyro_unit=count",
                        "--initial_gyro_gain=0.00021", "--json=" + json_path,
                        "--calibration_out=" + calibration, "--report=" + report});
  ASSERT_EQ(run.exit_status, 0) << run.stderr_text;
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  const nlohmann::json& g = json.at("gyroscope");
  const std::vector<std::string> expected = {
      "gyroscope_misalignment_yz", "gyroscope_misalignment_zy", "gyroscope_misalignment_zx",
      "gyroscope_misalignment_yx"};
  const std::vector<std::string> axes = {"y", "z", "z", "y"};
  const nlohmann::json& list = g.at("poorly_determined");
  ASSERT_EQ(list.size(), expected.size()) << list.dump(1);
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(list[i].at("parameter"), expected[i]);
    EXPECT_TRUE(list[i].at("sigma_over_threshold").get<bool>());
    const std::string suggestion = list[i].at("suggestion");
    EXPECT_NE(suggestion.find("turns about the sensor's " + axes[i] + " axis"), std::string::npos)
        << suggestion;
    EXPECT_NE(run.stdout_text.find("  " + expected[i] + " = "), std::string::npos);
  }
  const nlohmann::json& turned = g.at("turned_about_rad");
  EXPECT_GT(turned[0].get<double>(), 5.0 * (turned[1].get<double>() + turned[2].get<double>()));
  const nlohmann::json file = nlohmann::json::parse(testing::ReadText(calibration));
  EXPECT_EQ(file.at("gyroscope").at("poorly_determined"), list);
  const std::string verdict = g.at("verdict_text");
  EXPECT_NE(verdict.find("the session does not determine gyroscope_misalignment_yz"),
            std::string::npos)
      << verdict;
  EXPECT_NE(verdict.find("turns about y and z would determine them"), std::string::npos) << verdict;
  EXPECT_NE(run.stdout_text.find("Poorly determined, gyroscope (estimated and written"),
            std::string::npos);
  const std::string html = testing::ReadText(report);
  EXPECT_NE(html.find("Poorly determined by this session (gyroscope): gyroscope_misalignment_yz"),
            std::string::npos);  // apply names them in its summary, beside the accelerometer's
                                 // (none here).
  const testing::CommandResult applied = RunBinaryArgs(
      "apply", {"--calibration=" + calibration, "--in=" + csv, "--out=" + scratch.File("c.csv")});
  ASSERT_EQ(applied.exit_status, 0) << applied.stderr_text;
  EXPECT_NE(applied.stdout_text.find("poorly determined by the calibration's session, of the "
                                     "gyroscope (its gyroscope.poorly_determined says why and "
                                     "which turns would determine them): "
                                     "gyroscope_misalignment_yz, gyroscope_misalignment_zy"),
            std::string::npos)
      << applied.stdout_text;
}

// Another sensor's log: a gyroscope already in rad/s (gains within 2% of 1, offsets of 0.01
// rad/s, 6e-4 rad/s of noise, not quantised), columns named as a ROS-style export, at 200 Hz, and
// nothing said of the gyroscope on the command line: the unit comes from the columns' names, the
// gains start at 1, and both sensors are calibrated, the gyroscope's truth within 4 sigma.
TEST(GyroscopeCli, CalibratesAGyroscopeInRadPerSecondFromTheColumnsNames) {
  GyroscopeSessionDesign design;
  design.rate_hz = 200.0;
  design.gyroscope_in_counts = false;
  design.truth = GyroscopeParametersWithGain(1.012, 0.991, 1.004);
  design.truth[kGyroscopeMisalignmentXy] = 0.004;
  design.truth[kGyroscopeMisalignmentZx] = -0.007;
  design.offset = {0.011, -0.008, 0.013};
  design.gyroscope_noise = {6e-4, 6e-4, 6e-4};
  const std::vector<TriadHold> holds = GyroscopeDesignHolds(design, 31);
  GyroscopeSessionFit fit;
  ASSERT_TRUE(SimulateAndCalibrateGyroscope(design, holds, 32, {}, &fit).ok());
  const TriadLog& log = fit.session.log;
  testing::ScratchDir scratch;
  const std::string csv = scratch.File("imu.csv");
  {
    std::ofstream out(csv);
    out << "timestamp,acc_x,acc_y,acc_z,gyr_x_radps,gyr_y_radps,gyr_z_radps\n";
    for (size_t i = 0; i < log.size(); ++i) {
      out << StringPrintf("%.3f,%.0f,%.0f,%.0f,%.9g,%.9g,%.9g\n", log.timestamp_s[i],
                          log.output[i][0], log.output[i][1], log.output[i][2], log.gyroscope[i][0],
                          log.gyroscope[i][1], log.gyroscope[i][2]);
    }
  }
  const std::string json_path = scratch.File("out.json");
  const testing::CommandResult run = RunBinaryArgs(
      "calibrate_imu", {"--log=" + csv, "--mode=ml", "--g=9.81744", "--json=" + json_path});
  ASSERT_EQ(run.exit_status, 0) << run.stderr_text;
  const nlohmann::json g = nlohmann::json::parse(testing::ReadText(json_path)).at("gyroscope");
  ASSERT_TRUE(g.is_object()) << run.stdout_text;
  EXPECT_EQ(g.at("output_unit"), "rad/s");
  std::vector<double> truth(design.truth.begin(), design.truth.end());
  truth.insert(truth.end(), design.offset.begin(), design.offset.end());
  for (size_t i = 0; i < truth.size(); ++i) {
    const std::string name = g.at("parameter_order")[i];
    const double value = g.at("parameters").at(name);
    const double sigma = g.at("stddev").at(name);
    EXPECT_LT(std::abs(value - truth[i]), 4.0 * sigma) << name << " " << value << " +- " << sigma;
  }
}

TEST(GyroscopeCli, StudyReportsTheRefusalOfTurnsAboutOneAxisAndRefusesBadFlags) {
  const testing::CommandResult planar =
      RunBinaryArgs("gyroscope_study", {"--trials=10", "--turn_set=planar"});
  ASSERT_EQ(planar.exit_status, 0) << planar.stderr_text;
  EXPECT_NE(planar.stdout_text.find("verdict: REFUSED"), std::string::npos) << planar.stdout_text;
  testing::ExpectBadInputContract(RunBinaryArgs("gyroscope_study", {"--effects=warmup"}),
                                  "gyroscope_study", "unknown effect 'warmup'");
  testing::ExpectBadInputContract(RunBinaryArgs("gyroscope_study", {"--turn_set=cube"}),
                                  "gyroscope_study", "unknown turn set 'cube'");
}

}  // namespace
}  // namespace accelcal
