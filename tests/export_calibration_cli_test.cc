// export_calibration (issue 34, item 3; docs/calibration.md, "Exports"), end to end: the three
// exports of a real calibration read back by each format's own conventions and applied to the
// session as apply corrects it (tests/export_readback.py, numpy and yaml), the imu_tk pair and
// imucal's JSON of an example calibration checked here against T K (u - b) computed
// independently, and what a format cannot hold refused in one line with nothing written.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "gyroscope_calibration_example.h"
#include "io/calibration_file.h"
#include "io/imucal_calibration_json.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::ExpectBadInputContract;
using testing::RunBinaryArgs;
using testing::ScratchDir;

constexpr char kPython[] = "/usr/bin/python3";

std::string WriteCalibration(const ScratchDir& scratch, const std::string& name,
                             const CalibrationRecord& record) {
  return scratch.Write(name, CalibrationJson(record).dump(2) + "\n");
}

// The 21 numbers imu_tk's CalibratedTriad_::load reads (>> 21 times), T, K, b.
std::vector<double> ImuTkLoad(const std::string& text) {
  std::istringstream stream(text);
  std::vector<double> numbers(21);
  for (double& number : numbers) stream >> number;
  EXPECT_FALSE(stream.fail());
  return numbers;
}

Eigen::Vector3d ImuTkApply(const std::vector<double>& n, const Eigen::Vector3d& raw) {
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> t(n.data()), k(n.data() + 9);
  return t * k * (raw - Eigen::Vector3d(n[18], n[19], n[20]));
}

// accelcal's a = T K (u - b) written out from the record's named parameters.
Eigen::Vector3d AccelcalTriad(const CalibrationRecord& r, const Eigen::Vector3d& u) {
  auto p = [&](const char* name) { return r.values[r.IndexOf(name)]; };
  Eigen::Matrix3d t;
  t << 1, -p("misalignment_yz"), p("misalignment_zy"), 0, 1, -p("misalignment_zx"), 0, 0, 1;
  const Eigen::Vector3d v(p("gain_x") * (u[0] - p("offset_x")),
                          p("gain_y") * (u[1] - p("offset_y")),
                          p("gain_z") * (u[2] - p("offset_z")));
  return t * v;
}

Eigen::Vector3d AccelcalGyroscope(const GyroscopeCalibrationSection& g, const Eigen::Vector3d& u) {
  auto p = [&](const std::string& name) {
    for (size_t i = 0; i < g.parameter_order.size(); ++i)
      if (g.parameter_order[i] == "gyroscope_" + name) return g.values[i];
    ADD_FAILURE() << name;
    return 0.0;
  };
  Eigen::Matrix3d t;
  t << 1, -p("misalignment_yz"), p("misalignment_zy"), p("misalignment_xz"), 1,
      -p("misalignment_zx"), -p("misalignment_xy"), p("misalignment_yx"), 1;
  Eigen::Vector3d v;
  for (int k = 0; k < 3; ++k) {
    const std::string axis(1, "xyz"[k]);
    v[k] = p("gain_" + axis) * (u[k] - p("offset_" + axis));
  }
  return t * v;
}

const Eigen::Vector3d kRawAccelerometer(32768.0 + 2100.0, 32768.0 - 3000.0, 32768.0 + 2600.0);
const Eigen::Vector3d kRawGyroscope(4000.0, -9000.0, 15000.0);

TEST(ExportCalibrationCli, RoundTripsByEachFormatsOwnConventions) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  const testing::CommandResult result =
      testing::RunCommand(std::string(kPython) + " -I '" + ACCELCAL_SOURCE_DIR +
                          "/tests/export_readback.py' '" + ACCELCAL_BIN_DIR + "' '" + dir + "'");
  EXPECT_EQ(result.exit_status, 0) << result.stdout_text << result.stderr_text;
  EXPECT_NE(result.stdout_text.find("PASS"), std::string::npos) << result.stdout_text;
}

TEST(ExportCalibrationCli, ImuTkPairIsTKAndBAtFullPrecisionWithCommentsAfterTheNumbers) {
  ScratchDir scratch;
  const CalibrationRecord record = testing::ExampleTriadRecordWithGyroscope();
  const std::string calibration = WriteCalibration(scratch, "cal.json", record);
  const testing::CommandResult result = RunBinaryArgs(
      "export_calibration",
      {"--calibration=" + calibration, "--format=imu_tk", "--out=" + scratch.File("imu")});
  ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
  const std::string acc = testing::ReadText(scratch.File("imu_acc.calib"));
  const std::string gyro = testing::ReadText(scratch.File("imu_gyro.calib"));
  const Eigen::Vector3d a = ImuTkApply(ImuTkLoad(acc), kRawAccelerometer);
  const Eigen::Vector3d a_expected = AccelcalTriad(record, kRawAccelerometer);
  EXPECT_LT((a - a_expected).norm(), 1e-12 * a_expected.norm()) << a << "\n" << a_expected;
  const Eigen::Vector3d w = ImuTkApply(ImuTkLoad(gyro), kRawGyroscope);
  const Eigen::Vector3d w_expected = AccelcalGyroscope(record.gyroscope, kRawGyroscope);
  EXPECT_LT((w - w_expected).norm(), 1e-12 * w_expected.norm()) << w << "\n" << w_expected;
  // Provenance after the 21 numbers, where load never reads.
  EXPECT_NE(acc.find("\n# calibration: " + calibration + " (sha256 "), std::string::npos) << acc;
  EXPECT_EQ(acc.find('#'), acc.find("\n\n#") + 2) << acc;
}

TEST(ExportCalibrationCli, ImucalJsonIsReadByTheLibrarysReaderAndGivesTheSameValues) {
  ScratchDir scratch;
  const CalibrationRecord record = testing::ExampleTriadRecordWithGyroscope();
  const std::string calibration = WriteCalibration(scratch, "cal.json", record);
  for (const std::string unit : {"deg/s", "rad/s"}) {
    const std::string out = scratch.File("imucal.json");
    const testing::CommandResult result =
        RunBinaryArgs("export_calibration", {"--calibration=" + calibration, "--format=imucal",
                                             "--imucal_gyr_unit=" + unit, "--out=" + out});
    ASSERT_EQ(result.exit_status, 0) << result.stderr_text;
    ImucalCalibration imucal;
    ASSERT_TRUE(ReadImucalCalibrationJson(out, &imucal).ok());
    ASSERT_TRUE(imucal.has_gyroscope);
    const ImucalAccelerometer& acc = imucal.accelerometer;
    const Eigen::Vector3d a = acc.r_a.inverse() * acc.k_a.inverse() * (kRawAccelerometer - acc.b_a);
    const Eigen::Vector3d a_expected = AccelcalTriad(record, kRawAccelerometer);
    EXPECT_LT((a - a_expected).norm(), 1e-12 * a_expected.norm());
    const ImucalGyroscope& gyr = imucal.gyroscope;
    EXPECT_EQ(gyr.k_ga, Eigen::Matrix3d::Zero());
    const double per_radps = unit == "deg/s" ? 180.0 / M_PI : 1.0;
    const Eigen::Vector3d w = gyr.r_g.inverse() * gyr.k_g.inverse() *
                              (kRawGyroscope - gyr.k_ga * a - gyr.b_g) / per_radps;
    const Eigen::Vector3d w_expected = AccelcalGyroscope(record.gyroscope, kRawGyroscope);
    EXPECT_LT((w - w_expected).norm(), 1e-12 * w_expected.norm()) << unit;
    const nlohmann::json json = nlohmann::json::parse(testing::ReadText(out));
    EXPECT_EQ(json.at("gyr_unit"), unit);
    EXPECT_EQ(json.at("from_acc_unit"), "a.u.");
    EXPECT_EQ(json.at("cal_type"), "Ferraris");
    EXPECT_NE(json.at("comment").get<std::string>().find("sha256"), std::string::npos);
    // R_a's rows are unit vectors, K_a diagonal: imucal's own convention.
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(acc.r_a.row(i).norm(), 1.0, 1e-14);
    EXPECT_TRUE(acc.k_a.isDiagonal());
  }
}

// Issue 45: the Allan fits of the calibration's own two logs given the wrong way round (each in
// counts, so no unit check sees it) gave Kalibr noise densities off by 8.4x, exit 0. The
// calibration file records its logs' SHA-256 and each Allan JSON its log's: refused, naming the
// swap; the right way round writes the file.
TEST(ExportCalibrationCli, RefusesAllanFitsOfTheCalibrationsLogsSwapped) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  ScratchDir scratch;
  const std::string acc = dir + "/xsens_acc.mat";
  const std::string gyro = dir + "/xsens_gyro.mat";
  const std::string calibration = scratch.File("cal.json");
  ASSERT_EQ(RunBinaryArgs("calibrate_imu",
                          {"--log=" + acc, "--gyro_log=" + gyro, "--g=9.81744", "--mode=ml",
                           "--initial_gyro_gain=0.000159795", "--calibration_out=" + calibration})
                .exit_status,
            0);
  const std::string acc_allan = scratch.File("acc_allan.json");
  const std::string gyro_allan = scratch.File("gyro_allan.json");
  ASSERT_EQ(
      RunBinaryArgs("allan", {"--log=" + acc, "--unit=count", "--json=" + acc_allan}).exit_status,
      0);
  ASSERT_EQ(
      RunBinaryArgs("allan", {"--log=" + gyro, "--unit=count", "--json=" + gyro_allan}).exit_status,
      0);
  const std::string out = scratch.File("imu.yaml");
  ExpectBadInputContract(
      RunBinaryArgs("export_calibration",
                    {"--calibration=" + calibration, "--format=kalibr", "--allan=" + gyro_allan,
                     "--gyro_allan=" + acc_allan, "--out=" + out}),
      "export_calibration", "(--allan) is an Allan fit of " + calibration + "'s gyroscope log");
  EXPECT_FALSE(testing::PathExists(out));
  const testing::CommandResult right = RunBinaryArgs(
      "export_calibration", {"--calibration=" + calibration, "--format=kalibr",
                             "--allan=" + acc_allan, "--gyro_allan=" + gyro_allan, "--out=" + out});
  EXPECT_EQ(right.exit_status, 0) << right.stderr_text;
  EXPECT_TRUE(testing::PathExists(out));
}

TEST(ExportCalibrationCli, RefusesWhatAFormatCannotHoldAndWritesNothing) {
  ScratchDir scratch;
  const std::string triad_only =
      WriteCalibration(scratch, "triad.json", testing::ExampleTriadRecord());
  const std::string out = scratch.File("out");
  // imucal's calibrate() needs the gyroscope's matrices.
  ExpectBadInputContract(RunBinaryArgs("export_calibration", {"--calibration=" + triad_only,
                                                              "--format=imucal", "--out=" + out}),
                         "export_calibration", "no gyroscope section");
  // Kalibr: its gyroscope terms need the section, and the Allan fits are required.
  ExpectBadInputContract(RunBinaryArgs("export_calibration", {"--calibration=" + triad_only,
                                                              "--format=kalibr", "--out=" + out}),
                         "export_calibration", "--format=kalibr needs --allan and --gyro_allan");
  // An Allan fit that is not allan's JSON.
  const std::string with_gyroscope =
      WriteCalibration(scratch, "gyro.json", testing::ExampleTriadRecordWithGyroscope());
  ExpectBadInputContract(
      RunBinaryArgs("export_calibration",
                    {"--calibration=" + with_gyroscope, "--format=kalibr",
                     "--allan=" + with_gyroscope, "--gyro_allan=" + triad_only, "--out=" + out}),
      "export_calibration", "not allan's JSON");
  // An output that is an input, or a special file.
  ExpectBadInputContract(
      RunBinaryArgs("export_calibration", {"--calibration=" + with_gyroscope, "--format=imucal",
                                           "--out=" + with_gyroscope}),
      "export_calibration", "--out");
  ExpectBadInputContract(
      RunBinaryArgs("export_calibration",
                    {"--calibration=" + with_gyroscope, "--format=imucal", "--out=/dev/null"}),
      "export_calibration", "--out");
  ExpectBadInputContract(RunBinaryArgs("export_calibration", {"--calibration=" + with_gyroscope,
                                                              "--format=ros", "--out=" + out}),
                         "export_calibration", "kalibr, imu_tk or imucal");
  // A two-axis calibration has no z axis.
  CalibrationRecord two_axis;
  GeometryInfo geometry;
  ASSERT_TRUE(GeometryOf("two_axis", "m/s^2", &geometry).ok());
  two_axis.parameter_order = geometry.parameters;
  two_axis.values = Eigen::Vector4d(0.07, 0.01, -0.05, 0.02);
  two_axis.covariance = Eigen::Vector4d(1e-4, 1e-6, 1e-4, 1e-6).asDiagonal();
  two_axis.noise_variance = {0.25, 0.25};
  two_axis.noise_variance_from = "--noise_variance";
  const std::string two_axis_file = WriteCalibration(scratch, "two_axis.json", two_axis);
  ExpectBadInputContract(RunBinaryArgs("export_calibration", {"--calibration=" + two_axis_file,
                                                              "--format=imu_tk", "--out=" + out}),
                         "export_calibration", "geometry is two_axis");
  EXPECT_FALSE(testing::PathExists(out));
  EXPECT_FALSE(testing::PathExists(out + "_acc.calib"));
}

}  // namespace
}  // namespace accelcal
