// calibrate_imu --mode=imu_tk with a gyroscope, end to end (issue 32, item 2): on imu_tk's own
// Xsens pair, every figure imu_tk prints for the gyroscope is in the output and the JSON to its
// printed digits; the .calib files read back by imu_tk's load rules; the gyroscope's flags
// refused in one line, with nothing written.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/format.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::ExpectBadInputContract;
using testing::RunBinaryArgs;

// imu_tk's example (its apps/test_imu_calib.cpp): the accelerometer's flags of issue 20, and the
// gyroscope's start 1/6258 (rad/s)/count.
std::vector<std::string> XsensPairArgs(const std::string& dir) {
  return {"--log=" + dir + "/xsens_acc.mat",
          "--gyro_log=" + dir + "/xsens_gyro.mat",
          "--g=9.81744",
          "--mode=imu_tk",
          "--init_rest_s=50",
          "--initial_offset=32768"};
}

std::vector<std::string> With(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

// A number as imu_tk's cout prints it: default precision, 6 significant digits.
std::string Printed(double value) { return StringPrintf("%g", value); }

// imu_tk's CalibratedTriad_::load: 9 numbers (the misalignment matrix, row-major), 9 (the scale
// matrix), 3 (the bias vector), read with >> whatever the spacing. Also says whether anything but
// blanks follows them.
struct LoadedTriad {
  bool opened = false;
  bool complete = false;
  bool trailing_text = false;
  std::array<double, 9> misalignment{};
  std::array<double, 9> scale{};
  std::array<double, 3> bias{};
};

LoadedTriad LoadLikeImuTk(const std::string& path) {
  LoadedTriad triad;
  std::ifstream file(path);
  triad.opened = file.is_open();
  if (!triad.opened) return triad;
  for (double& value : triad.misalignment) file >> value;
  for (double& value : triad.scale) file >> value;
  for (double& value : triad.bias) file >> value;
  triad.complete = static_cast<bool>(file);
  std::string rest;
  triad.trailing_text = static_cast<bool>(file >> rest);
  return triad;
}

// Loads `path` as imu_tk does, expecting its 21 numbers and nothing after them.
LoadedTriad LoadExpectingTheWholeFile(const std::string& path) {
  const LoadedTriad triad = LoadLikeImuTk(path);
  EXPECT_TRUE(triad.opened && triad.complete) << path;
  EXPECT_FALSE(triad.trailing_text) << path;
  return triad;
}

bool Exists(const std::string& path) {
  struct stat info;
  return stat(path.c_str(), &info) == 0;
}

// imu_tk's printout on the pair (issue 32): each line, as printed.
constexpr const char* kImuTkPrintedLines[] = {"Gyroscopes calibration: residual 0.00150696",
                                              "Misalignment Matrix",
                                              "         1 0.00593634 0.00111101",
                                              "0.00808812          1 -0.0535569",
                                              " 0.0253067 -0.0025513          1",
                                              "Scale Matrix",
                                              "0.000209295           0           0",
                                              "          0 0.000209899           0",
                                              "          0           0 0.000209483",
                                              "Bias Vector",
                                              "32777.1",
                                              "32459.8",
                                              "32511.8",
                                              "Gyroscopes calibration: inverse scale factors:",
                                              "4777.96",
                                              "4764.21",
                                              "4773.66"};

TEST(CalibrateImuGyroscopeCli, PrintsEveryFigureImuTkPrintsForTheGyroscopeOnItsXsensPair) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  const std::string json_path = scratch.File("out.json");
  // --initial_gyro_gain=0.000159795 is also what the refusal of counts without it suggests.
  const testing::CommandResult result = RunBinaryArgs(
      "calibrate_imu",
      With(XsensPairArgs(dir), {"--initial_gyro_gain=0.000159795", "--json=" + json_path}));
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::string& out = result.stdout_text;
  const size_t section = out.find("\nGyroscope: imu_tk's gyroscope calibration");
  ASSERT_NE(section, std::string::npos) << out;
  const std::string gyroscope = out.substr(section);
  // Each line of imu_tk's printout, whole, in the section (indented by two).
  for (const char* line : kImuTkPrintedLines) {
    EXPECT_NE(gyroscope.find("\n  " + std::string(line) + "\n"), std::string::npos)
        << "'" << line << "' not printed:\n"
        << gyroscope;
  }
  EXPECT_NE(gyroscope.find("(imu_tk printed exactly these lines on this log)"), std::string::npos);
  // The parameters' table: the estimate beside imu_tk's value and the datasheet's.
  EXPECT_NE(gyroscope.find("1/4777.96        1/4777.96        1/4778"), std::string::npos)
      << gyroscope;
  EXPECT_NE(gyroscope.find("gyroscope_offset_y         count            32459.803        "
                           "32459.8          32466"),
            std::string::npos)
      << gyroscope;
  EXPECT_NE(gyroscope.find("residual: 0.00150696 ("), std::string::npos);
  EXPECT_NE(gyroscope.find("residual angle over the 37 turns: median"), std::string::npos);
  // The log line says the gyroscope is calibrated here; the accelerometer's answer is unchanged.
  EXPECT_NE(out.find("read: gyroscope: read (51175 samples); calibrated below by imu_tk's rules"),
            std::string::npos);
  EXPECT_NE(out.find("Chosen: k = 6, the lowest final cost 0.120131"), std::string::npos);

  // The JSON: the same figures to the same digits.
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  const nlohmann::json& g = json["gyroscope"];
  ASSERT_TRUE(g.is_object()) << json.dump(1).substr(0, 400);
  EXPECT_EQ(Printed(g["cost"].get<double>()), "0.00150696");
  const std::array<std::array<const char*, 3>, 3> misalignment = {
      {{"1", "0.00593634", "0.00111101"},
       {"0.00808812", "1", "-0.0535569"},
       {"0.0253067", "-0.0025513", "1"}}};
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      EXPECT_EQ(Printed(g["misalignment_matrix"][row][column].get<double>()),
                misalignment[row][column])
          << row << "," << column;
    }
  }
  const std::array<const char*, 3> scale = {"0.000209295", "0.000209899", "0.000209483"};
  const std::array<const char*, 3> bias = {"32777.1", "32459.8", "32511.8"};
  const std::array<const char*, 3> inverse = {"4777.96", "4764.21", "4773.66"};
  for (int k = 0; k < 3; ++k) {
    const std::string axis(1, "xyz"[k]);
    EXPECT_EQ(Printed(g["scale_matrix"][k][k].get<double>()), scale[k]);
    EXPECT_EQ(Printed(g["parameters"]["gyroscope_gain_" + axis].get<double>()), scale[k]);
    EXPECT_EQ(Printed(g["bias_vector"][k].get<double>()), bias[k]);
    EXPECT_EQ(Printed(g["offset"][k].get<double>()), bias[k]);
    EXPECT_EQ(Printed(g["inverse_gain"][axis].get<double>()), inverse[k]);
  }
  EXPECT_EQ(Printed(g["parameters"]["gyroscope_misalignment_yz"].get<double>()), "-0.00593634");
  EXPECT_EQ(Printed(g["parameters"]["gyroscope_misalignment_xy"].get<double>()), "-0.0253067");
  EXPECT_EQ(g["units"]["gyroscope_gain_x"], "(rad/s)/count");
  EXPECT_EQ(g["turns"].size(), 37u);
  EXPECT_EQ(g["references"]["imu_tk_printed_residual"], "0.00150696");
  EXPECT_EQ(g["imu_tk_printout"], g["references"]["imu_tk_printout"]);
}

TEST(CalibrateImuGyroscopeCli, WritesImuTksCalibFilesThatItsLoadReadsBack) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  const std::string prefix = scratch.File("test_imu");
  const std::string json_path = scratch.File("out.json");
  const testing::CommandResult result = RunBinaryArgs(
      "calibrate_imu",
      With(XsensPairArgs(dir), {"--initial_gyro_gain=0.000159795", "--imu_tk_calib_out=" + prefix,
                                "--json=" + json_path}));
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find(prefix + "_acc.calib, " + prefix + "_gyro.calib"),
            std::string::npos);
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));

  // The gyroscope's file is imu_tk's printed matrices, blank line after each, byte for byte.
  EXPECT_EQ(testing::ReadText(prefix + "_gyro.calib"),
            "         1 0.00593634 0.00111101\n"
            "0.00808812          1 -0.0535569\n"
            " 0.0253067 -0.0025513          1\n\n"
            "0.000209295           0           0\n"
            "          0 0.000209899           0\n"
            "          0           0 0.000209483\n\n"
            "32777.1\n32459.8\n32511.8\n\n");
  const LoadedTriad gyroscope = LoadExpectingTheWholeFile(prefix + "_gyro.calib");
  const nlohmann::json& g = json["gyroscope"];
  for (int i = 0; i < 9; ++i) {
    const double expected = g["misalignment_matrix"][i / 3][i % 3].get<double>();
    EXPECT_NEAR(gyroscope.misalignment[i], expected, 5e-6 * std::fabs(expected) + 1e-12) << i;
    const double expected_scale = g["scale_matrix"][i / 3][i % 3].get<double>();
    EXPECT_NEAR(gyroscope.scale[i], expected_scale, 5e-6 * std::fabs(expected_scale)) << i;
  }
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(gyroscope.bias[k], g["offset"][k].get<double>(), 0.05) << k;

  // The accelerometer's: imu_tk's upper-triangular T (its lower angles 0), gains and offsets.
  const LoadedTriad accelerometer = LoadExpectingTheWholeFile(prefix + "_acc.calib");
  const nlohmann::json& p = json["parameters"];
  const double yz = p["misalignment_yz"], zy = p["misalignment_zy"], zx = p["misalignment_zx"];
  const std::array<double, 9> t = {1, -yz, zy, 0, 1, -zx, 0, 0, 1};
  for (int i = 0; i < 9; ++i)
    EXPECT_NEAR(accelerometer.misalignment[i], t[i], 5e-6 * std::fabs(t[i])) << i;
  for (int k = 0; k < 3; ++k) {
    const std::string axis(1, "xyz"[k]);
    const double gain = p["gain_" + axis];
    EXPECT_NEAR(accelerometer.scale[4 * k], gain, 5e-6 * gain) << axis;
    EXPECT_NEAR(accelerometer.bias[k], p["offset_" + axis].get<double>(), 0.05) << axis;
  }
  EXPECT_EQ(accelerometer.scale[1], 0.0);
  // imu_tk builds the accelerometer's T from (yz, zy, zx, 0, 0, 0): its -mis_xy is -0, and
  // Eigen prints it so; the third line's first entry.
  std::istringstream lines(testing::ReadText(prefix + "_acc.calib"));
  std::string line;
  for (int i = 0; i < 3; ++i) std::getline(lines, line);
  std::istringstream third(line);
  std::string first;
  third >> first;
  EXPECT_EQ(first, "-0") << line;
}

TEST(CalibrateImuGyroscopeCli, RefusesAGyroscopeInCountsWithoutItsGainAndWritesNothing) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  const std::string prefix = scratch.File("test_imu");
  const std::string json_path = scratch.File("out.json");
  const testing::CommandResult result = RunBinaryArgs(
      "calibrate_imu",
      With(XsensPairArgs(dir), {"--imu_tk_calib_out=" + prefix, "--json=" + json_path}));
  ExpectBadInputContract(result, "calibrate_imu", "--initial_gyro_gain=0.000159795");
  // The way to compute it from a datasheet, in both of its units.
  EXPECT_NE(result.stderr_text.find("G = 1/S for a datasheet sensitivity S in counts per rad/s"),
            std::string::npos)
      << result.stderr_text;
  EXPECT_NE(result.stderr_text.find("counts per deg/s"), std::string::npos);
  EXPECT_FALSE(Exists(json_path));
  EXPECT_FALSE(Exists(prefix + "_acc.calib"));
  EXPECT_FALSE(Exists(prefix + "_gyro.calib"));
}

// A log that carries the gyroscope's columns in counts beside the accelerometer's, with nothing
// said of the gyroscope: the accelerometer is calibrated as without them (good input is never
// refused), and the gyroscope is left uncalibrated, said so with the flag that would calibrate it.
TEST(CalibrateImuGyroscopeCli, AnAccelerometerRunIsNotRefusedForGyroscopeColumnsInCounts) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  std::ifstream acc(dir + "/xsens_acc.mat"), gyro(dir + "/xsens_gyro.mat");
  std::string a, g, csv = "t,ax,ay,az,gx,gy,gz\n";
  while (std::getline(acc, a) && std::getline(gyro, g)) {
    std::istringstream as(a), gs(g);
    double t, ax, ay, az, gt, gx, gy, gz;
    as >> t >> ax >> ay >> az;
    gs >> gt >> gx >> gy >> gz;
    csv += StringPrintf("%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", t, ax, ay, az, gx, gy, gz);
  }
  const std::string log = scratch.Write("xsens_imu.csv", csv);
  const testing::CommandResult result =
      RunBinaryArgs("calibrate_imu", {"--log=" + log, "--g=9.81744", "--mode=imu_tk",
                                      "--init_rest_s=50", "--initial_offset=32768"});
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("Chosen: k = 6, the lowest final cost 0.120131"),
            std::string::npos)
      << result.stdout_text;
  EXPECT_NE(result.stdout_text.find("gyroscope: read (51175 samples); not calibrated: its outputs "
                                    "are counts"),
            std::string::npos)
      << result.stdout_text;
  EXPECT_EQ(result.stdout_text.find("Gyroscope: imu_tk's gyroscope calibration"),
            std::string::npos);
  // The flag it names calibrates it.
  const testing::CommandResult followed = RunBinaryArgs(
      "calibrate_imu", {"--log=" + log, "--g=9.81744", "--mode=imu_tk", "--init_rest_s=50",
                        "--initial_offset=32768", "--initial_gyro_gain=0.000159795"});
  ASSERT_EQ(followed.exit_status, 0) << followed.stderr_text;
  EXPECT_NE(followed.stdout_text.find("Gyroscopes calibration: residual 0.00150696"),
            std::string::npos);
}

TEST(CalibrateImuGyroscopeCli, RefusesAUnitTheGyroscopeContradictsAndAnUnknownOne) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  ExpectBadInputContract(
      RunBinaryArgs("calibrate_imu", With(XsensPairArgs(dir), {"--gyro_unit=rpm"})),
      "calibrate_imu", "--gyro_unit: 'rpm' is not a gyroscope unit; say count");
  // Counts read as rad/s: a rest of 32777 "rad/s" is no gyroscope's offset.
  ExpectBadInputContract(
      RunBinaryArgs("calibrate_imu", With(XsensPairArgs(dir), {"--gyro_unit=rad/s"})),
      "calibrate_imu", "are the outputs raw counts? give --gyro_unit=count");
  // The gyroscope's flags without a gyroscope.
  ExpectBadInputContract(
      RunBinaryArgs("calibrate_imu", {"--log=" + dir + "/xsens_acc.mat", "--g=9.81744",
                                      "--initial_gyro_gain=0.000159795"}),
      "calibrate_imu", "--initial_gyro_gain is for the gyroscope, and the log has none");
}

// Mode ml on the Xsens pair: the gyroscope calibrated jointly with the accelerometer's poses,
// every parameter with a sigma. Discovery finds a g-sensitivity (chi2 173 on 9), so the
// calibration is the extended model (issue 44, item 7): the 12 and G's 9 terms, the 12 unknowns'
// fit beside them as the baseline, which is imu_tk's model and within 2 sigma of imu_tk's nine
// estimates (its offsets are its initial rest's, which the session's poses put 4 to 11 sigma
// away). The turns fit the extended model: chi2 of the 74 turn components within 3 sd of 74. The
// baseline needed a wander of 4-7 counts between poses, which left four angles and gain_z poorly
// determined; G accounts for most of it (a wander of under 1 count remains), and the extended
// model determines every unknown. --gyro_bias and --imu_tk_calib_out belong to imu_tk's mode.
TEST(CalibrateImuGyroscopeCli, MlModeCalibratesTheGyroscopeWithSigmaBesideImuTk) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  std::vector<std::string> ml = XsensPairArgs(dir);
  ml[3] = "--mode=ml";
  ExpectBadInputContract(RunBinaryArgs("calibrate_imu", With(ml, {"--initial_gyro_gain=0.000159795",
                                                                  "--gyro_bias=rest"})),
                         "calibrate_imu", "--gyro_bias belongs to --mode=imu_tk");
  testing::ScratchDir scratch;
  const std::string json_path = scratch.File("gyroscope_ml.json");
  const std::string report_path = scratch.File("gyroscope_ml.html");
  const testing::CommandResult result =
      RunBinaryArgs("calibrate_imu", With(ml, {"--initial_gyro_gain=0.000159795",
                                               "--json=" + json_path, "--report=" + report_path}));
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("Gyroscope: maximum likelihood"), std::string::npos);
  EXPECT_NE(result.stdout_text.find("Earth's rate"), std::string::npos);
  const nlohmann::json json = nlohmann::json::parse(testing::ReadText(json_path));
  const nlohmann::json& g = json.at("gyroscope");
  ASSERT_TRUE(g.is_object());
  const nlohmann::json& order = g.at("parameter_order");
  ASSERT_EQ(g.at("effect_terms").size(), 9u);
  ASSERT_EQ(order.size(), 21u);
  EXPECT_EQ(order[12], "gyroscope_g_sensitivity_xx");
  const nlohmann::json& baseline = g.at("baseline");
  ASSERT_TRUE(baseline.is_object());
  for (size_t i = 0; i < order.size(); ++i) {
    const std::string name = order[i];
    const double sigma = g.at("stddev").at(name);
    ASSERT_GT(sigma, 0.0) << name;
    EXPECT_NEAR(sigma * sigma, g.at("covariance")[i][i].get<double>(), 1e-9 * sigma * sigma);
    if (i >= 9) continue;
    const double imu_tk = g.at("imu_tk").at("parameters").at(name);
    const double value = baseline.at("parameters").at(name);
    EXPECT_LT(std::abs(value - imu_tk), 2.0 * baseline.at("stddev").at(name).get<double>()) << name;
  }
  // Gains to better than 0.1%: 4782 +- 1 counts per rad/s on x.
  const double gain_x = g.at("parameters").at("gyroscope_gain_x");
  EXPECT_LT(g.at("stddev").at("gyroscope_gain_x").get<double>() / gain_x, 1e-3);
  EXPECT_GT(g.at("fit").at("p_value").get<double>(), 0.01);
  const double turns = g.at("fit").at("chi2_turns");
  EXPECT_LT(std::abs(turns - 74.0), 3.0 * std::sqrt(2.0 * 74.0)) << turns;
  EXPECT_EQ(g.at("turns").size(), 37u);
  const double wander = g.at("bias_wander_variance")[1];
  EXPECT_LT(wander, 1.0);  // counts^2: the baseline's was 7.31^2
  EXPECT_GT(g.at("discovery").at("bias_wander").get<bool>() ? 1 : 0, 0);
  EXPECT_EQ(g.at("poorly_determined"), nlohmann::json::array());
  for (int k = 0; k < 3; ++k) EXPECT_GT(g.at("turned_about_rad")[k].get<double>(), 40.0);
  // One gyroscope verdict, the same in the table, the JSON and the HTML report.
  const std::string verdict = g.at("verdict_text");
  const std::string code = g.at("verdict");
  EXPECT_NE(result.stdout_text.find("Verdict (gyroscope, " + code + "): " + verdict),
            std::string::npos);
  const std::string html = testing::ReadText(report_path);
  EXPECT_NE(html.find("6. The gyroscope"), std::string::npos);
  EXPECT_NE(html.find("Verdict (gyroscope, " + code + "): " + verdict), std::string::npos);
}

}  // namespace
}  // namespace accelcal
