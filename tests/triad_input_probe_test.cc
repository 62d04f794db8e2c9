// Inputs that do not say what they claim, end to end through the triad binaries (the probe of
// 2026-11-24): a log with a gap given to a calibration, a damaged sample given to apply, a log
// in m/s^2 said to be in counts given to allan. Each is one line on stderr, exit status 2 and
// nothing written; the same inputs without the damage are accepted.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/format.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::ExpectBadInputContract;
using testing::RunBinary;

// The first `lines` lines of imu_tk's Xsens log, each passed through `edit(line_index, t_s, u)`
// (which may change the time and the outputs), in its own whitespace layout.
template <typename Edit>
std::string XsensLines(const std::string& dir, int lines, Edit edit) {
  std::ifstream file(dir + "/xsens_acc.mat");
  std::string text;
  std::string line;
  for (int j = 0; j < lines && std::getline(file, line); ++j) {
    std::istringstream fields(line);
    double t_s = 0.0, u[3] = {0.0, 0.0, 0.0};
    fields >> t_s >> u[0] >> u[1] >> u[2];
    edit(j, &t_s, u);
    text += StringPrintf("%.9g %.9g %.9g %.9g\n", t_s, u[0], u[1], u[2]);
  }
  return text;
}

TEST(TriadInputProbe, CalibrationRefusesALogWithAGapInTime) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  // 30 s missing at t = 250 s, inside a pose: its mean is unchanged, but the noise model would
  // take the pose for 30 s longer than it is.
  const std::string log =
      scratch.Write("gap.txt", XsensLines(dir, 60000, [](int j, double* t_s, double*) {
                      if (j >= 25000) *t_s += 30.0;
                    }));
  const std::string json = scratch.File("out.json");
  const testing::CommandResult result =
      RunBinary("calibrate_imu", "--log=" + log + " --g=9.81744 --mode=ml --json=" + json);
  ExpectBadInputContract(result, "calibrate_imu", "the log has a gap");
  EXPECT_NE(result.stderr_text.find("sample 25001"), std::string::npos) << result.stderr_text;
  EXPECT_FALSE(std::ifstream(json).good());
}

TEST(TriadInputProbe, ApplyRefusesASampleBeyondAnyAccelerometersRange) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  const std::string cal = scratch.File("cal.json");
  const testing::CommandResult calibrated =
      RunBinary("calibrate_imu",
                "--log=" + dir + "/xsens_acc.mat --g=9.81744 --mode=ml --calibration_out=" + cal);
  ASSERT_EQ(calibrated.exit_status, 0) << calibrated.stderr_text;
  const std::string out = scratch.File("corrected.csv");
  for (const double damaged : {1e308, 1e15}) {
    const std::string in =
        scratch.Write("damaged.txt", XsensLines(dir, 300, [damaged](int j, double*, double* u) {
                        if (j == 150) u[1] = damaged;
                      }));
    const testing::CommandResult result =
        RunBinary("apply", "--calibration=" + cal + " --in=" + in + " --out=" + out);
    ExpectBadInputContract(result, "apply", "sample 151 (t = ");
    EXPECT_NE(result.stderr_text.find("beyond any accelerometer's range"), std::string::npos)
        << result.stderr_text;
    EXPECT_FALSE(std::ifstream(out).good()) << damaged;
  }
  const std::string whole =
      scratch.Write("whole.txt", XsensLines(dir, 300, [](int, double*, double*) {}));
  const testing::CommandResult result =
      RunBinary("apply", "--calibration=" + cal + " --in=" + whole + " --out=" + out);
  EXPECT_EQ(result.exit_status, 0) << result.stderr_text;
  EXPECT_EQ(testing::ReadText(out).find("nan"), std::string::npos);
}

TEST(TriadInputProbe, AllanRefusesALogInAnotherUnitThanStated) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  testing::ScratchDir scratch;
  // The initial rest converted to m/s^2 by the datasheet's offsets and scales.
  const std::string log = scratch.Write(
      "rest_mps2.txt", XsensLines(dir, 5000, [](int, double*, double* u) {
        const double offset[3] = {33123, 33276, 32360}, counts_per_mps2[3] = {415, 413, 415};
        for (int k = 0; k < 3; ++k) u[k] = (u[k] - offset[k]) / counts_per_mps2[k];
      }));
  const std::string json = scratch.File("allan.json");
  const testing::CommandResult refused =
      RunBinary("allan", "--log=" + log + " --bootstrap=100 --json=" + json);
  ExpectBadInputContract(refused, "allan", "looks already converted to m/s^2");
  EXPECT_FALSE(std::ifstream(json).good());
  const testing::CommandResult stated =
      RunBinary("allan", "--log=" + log + " --unit=m/s^2 --bootstrap=100 --json=" + json);
  EXPECT_EQ(stated.exit_status, 0) << stated.stderr_text;
}

// One session folder given under two names (a copy, or here a link) would be two sessions that
// agree exactly: the between-session spread would come out too small.
TEST(TriadInputProbe, RepeatabilityRefusesOneSessionUnderTwoNames) {
  const std::string dir = testing::DataDirFrom("ACCELCAL_MIMU4444_DATA",
                                               ACCELCAL_DEFAULT_MIMU4444_DATA, "run3/imu8.csv");
  if (dir.empty()) GTEST_SKIP() << "mimu4444 data not found: set ACCELCAL_MIMU4444_DATA";
  testing::ScratchDir scratch;
  const std::string sessions = scratch.File("sessions");
  std::filesystem::create_directory(sessions);
  std::filesystem::create_directory_symlink(dir + "/run1", sessions + "/run1");
  std::filesystem::create_directory_symlink(dir + "/run2", sessions + "/run2");
  std::filesystem::create_directory_symlink(dir + "/run2", sessions + "/run3");
  const std::string json = scratch.File("out.json");
  const testing::CommandResult result =
      RunBinary("triad_repeatability", "--data_dir=" + sessions + " --trials=0 --json=" + json);
  ExpectBadInputContract(result, "triad_repeatability",
                         "/run3/imu1.csv holds the same bytes as " + sessions + "/run2/imu1.csv");
  EXPECT_FALSE(std::ifstream(json).good());
}

}  // namespace
}  // namespace accelcal
