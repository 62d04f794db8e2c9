// io/kalibr_imu_yaml and io/calibration_export on hand-made inputs: Kalibr's terms from an Allan
// fit, resolved or bounded by its curve, carried through a calibration's matrix and a gain; what
// a format cannot hold refused (docs/calibration.md, "Exports").

#include "io/calibration_export.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gyroscope_calibration_example.h"
#include "io/kalibr_imu_yaml.h"
#include "test_support.h"

namespace accelcal {
namespace {

// allan's JSON for a log in `output_unit` with results = gain * output: per axis N = n[k] and
// K = k[k] (resolved when > 0), and two curve points whose upper limits bound K.
nlohmann::json AllanJson(const std::string& output_unit, double gain, const Eigen::Vector3d& n,
                         const Eigen::Vector3d& k) {
  nlohmann::json axes;
  for (int a = 0; a < 3; ++a) {
    const bool resolved = k[a] > 0.0;
    axes[std::string(1, "xyz"[a])] = {
        {"white_noise", {{"fitted", true}, {"resolved", true}, {"value", n[a]}}},
        {"random_walk", {{"fitted", true}, {"resolved", resolved}, {"value", k[a]}, {"high", 0.0}}},
        {"points",
         {{{"tau_s", 1.0}, {"adev_high", 2.0 * (a + 1)}},
          {{"tau_s", 12.0}, {"adev_high", 1.0 * (a + 1)}}}}};
  }
  return {{"problem", "allan"},
          {"output_unit", output_unit},
          {"gain", gain},
          {"sample_period_s", 0.005},
          {"axes", axes}};
}

TEST(KalibrNoiseFromAllan, ResolvedTermsCarriedThroughTheMatrixAndTheGain) {
  Eigen::Matrix3d m;
  m << 2.0, 0.1, 0.0, 0.0, 3.0, 0.2, 0.0, 0.0, 4.0;
  const Eigen::Vector3d n(0.3, 0.4, 0.5), k(0.01, 0.02, 0.03);
  KalibrSensorNoise noise;
  ASSERT_TRUE(
      KalibrNoiseFromAllan(AllanJson("count", 2.0, n, k), "a.json", "count", m, "gyroscope", &noise)
          .ok());
  // Terms in the output unit are the JSON's over the gain; axis i's is sqrt(sum_k m_ik^2 t_k^2).
  const Eigen::Vector3d n_out = n / 2.0, k_out = k / 2.0;
  double density = 0.0, walk = 0.0;
  for (int i = 0; i < 3; ++i) {
    density = std::max(
        density,
        std::sqrt((m.row(i).transpose().cwiseAbs2().cwiseProduct(n_out.cwiseAbs2())).sum()));
    walk = std::max(
        walk, std::sqrt((m.row(i).transpose().cwiseAbs2().cwiseProduct(k_out.cwiseAbs2())).sum()));
  }
  EXPECT_NEAR(noise.noise_density, density, 1e-15 * density);
  EXPECT_NEAR(noise.random_walk, walk, 1e-15 * walk);
  EXPECT_DOUBLE_EQ(noise.update_rate_hz, 200.0);
}

TEST(KalibrNoiseFromAllan, UnresolvedRandomWalkIsTheLargestTheCurveAllows) {
  const Eigen::Vector3d n(0.3, 0.4, 0.5);
  KalibrSensorNoise noise;
  ASSERT_TRUE(KalibrNoiseFromAllan(AllanJson("count", 1.0, n, Eigen::Vector3d::Zero()), "a.json",
                                   "count", Eigen::Matrix3d::Identity(), "accelerometer", &noise)
                  .ok());
  // z: min(sqrt(3/1) 6, sqrt(3/12) 3) = 1.5.
  EXPECT_DOUBLE_EQ(noise.random_walk, 1.5);
  ASSERT_FALSE(noise.notes.empty());
  EXPECT_NE(noise.notes[0].find("not resolved"), std::string::npos) << noise.notes[0];
}

TEST(KalibrNoiseFromAllan, RefusesAnotherUnitOrNotAllansJson) {
  KalibrSensorNoise noise;
  const Eigen::Vector3d n(0.3, 0.4, 0.5), k(0.01, 0.02, 0.03);
  EXPECT_ERROR_CONTAINS(KalibrNoiseFromAllan(AllanJson("m/s^2", 1.0, n, k), "a.json", "count",
                                             Eigen::Matrix3d::Identity(), "accelerometer", &noise),
                        "a.json: output_unit is \"m/s^2\"");
  EXPECT_ERROR_CONTAINS(KalibrNoiseFromAllan(nlohmann::json::object(), "a.json", "count",
                                             Eigen::Matrix3d::Identity(), "accelerometer", &noise),
                        "not allan's JSON");
}

TEST(ExportCalibration, KalibrRefusesOneLogsAllanFitGivenForBothSensors) {
  ExportOptions options;
  options.format = ExportFormat::kKalibr;
  options.out = "imu.yaml";
  const Eigen::Vector3d n(0.3, 0.4, 0.5), k(0.01, 0.02, 0.03);
  options.allan = AllanJson("count", 1.0, n, k);
  options.allan["input_files"] = {{"log", {{"path", "acc.mat"}, {"sha256", "ab12"}}}};
  options.gyro_allan = options.allan;
  options.allan_path = "acc.json";
  options.gyro_allan_path = "gyro.json";
  std::vector<ExportedFile> files;
  std::vector<std::string> notes;
  EXPECT_ERROR_CONTAINS(ExportCalibration(testing::ExampleTriadRecordWithGyroscope(), "cal.json",
                                          options, &files, &notes),
                        "acc.json and gyro.json are Allan fits of the same log");
  // Two logs: the example's terms go through (the gyroscope's unit is count, as the fits').
  options.gyro_allan["input_files"]["log"]["sha256"] = "cd34";
  const Status status = ExportCalibration(testing::ExampleTriadRecordWithGyroscope(), "cal.json",
                                          options, &files, &notes);
  EXPECT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(files.size(), 1u);
  EXPECT_NE(files[0].contents.find("update_rate: 200  # Hz"), std::string::npos);
}

KalibrImuConfig ExampleKalibrConfig(const std::string& gyroscope_note) {
  KalibrImuConfig config;
  config.accelerometer.noise_density = 0.006;
  config.accelerometer.random_walk = 0.0002;
  config.gyroscope.noise_density = 0.0004;
  config.gyroscope.random_walk = 4e-6;
  config.gyroscope.notes = {gyroscope_note};
  config.update_rate_hz = 200.0;
  return config;
}

TEST(KalibrImuYaml, WritesTheSixKeysWithUnitsAndCommentsOnly) {
  const std::string text = KalibrImuYamlText(ExampleKalibrConfig("a note"), {"from here"});
  EXPECT_EQ(text,
            "# from here\n"
            "accelerometer_noise_density: 0.0060000000000000001  # m/s^2/sqrt(Hz)\n"
            "accelerometer_random_walk: 0.00020000000000000001  # m/s^3/sqrt(Hz)\n"
            "gyroscope_noise_density: 0.00040000000000000002  # rad/s/sqrt(Hz)\n"
            "gyroscope_random_walk: 3.9999999999999998e-06  # rad/s^2/sqrt(Hz)\n"
            "update_rate: 200  # Hz\n"
            "rostopic: /imu0\n"
            "# a note\n");
}

// A comment is one line whatever it quotes (common/line_text.h; issue 45): a path with a line
// break would otherwise start a key of its own.
TEST(KalibrImuYaml, ACommentWithALineBreakStaysOneComment) {
  const std::string text = KalibrImuYamlText(ExampleKalibrConfig("from b\nupdate_rate: 1"),
                                             {"calibration: a\nrostopic: /x"});
  EXPECT_EQ(text.find("\nrostopic: /x"), std::string::npos) << text;
  EXPECT_EQ(text.find("\nupdate_rate: 1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("# calibration: a\\nrostopic: /x\n"), std::string::npos) << text;
  EXPECT_NE(text.find("# from b\\nupdate_rate: 1\n"), std::string::npos) << text;
}

TEST(ExportCalibration, ImuTkWithoutAGyroscopeWritesTheAccelerometersFileAlone) {
  ExportOptions options;
  options.format = ExportFormat::kImuTk;
  options.out = "prefix";
  std::vector<ExportedFile> files;
  std::vector<std::string> notes;
  ASSERT_TRUE(
      ExportCalibration(testing::ExampleTriadRecord(), "cal.json", options, &files, &notes).ok());
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0].path, "prefix_acc.calib");
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("prefix_gyro.calib not written"), std::string::npos);
}

TEST(ExportCalibration, ImucalRefusesAGyroscopeUnitItDoesNotKnow) {
  ExportOptions options;
  options.format = ExportFormat::kImucal;
  options.out = "imucal.json";
  options.imucal_gyr_unit = "rpm";
  std::vector<ExportedFile> files;
  std::vector<std::string> notes;
  EXPECT_ERROR_CONTAINS(ExportCalibration(testing::ExampleTriadRecordWithGyroscope(), "cal.json",
                                          options, &files, &notes),
                        "--imucal_gyr_unit is 'rpm'");
  EXPECT_TRUE(files.empty());
}

}  // namespace
}  // namespace accelcal
