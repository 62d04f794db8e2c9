// Refusals that name their cause (issue 35, item 6), end to end through the binaries: each input
// is refused in one line that says what it is (an encoding, line ends, a number beyond a double,
// the wrong geometry, the output's resolution, clipped samples, a gyroscope), not only what
// failed downstream of it. The inputs are made here: simulated sessions (simulation/
// triad_log_simulator.h) quantised, clipped or taken from the gyroscope, written as a logger's CSV.
// And a 100 Hz log whose time column is the sample index (item 4).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "common/format.h"
#include "gyroscope_calibration_example.h"
#include "io/calibration_file.h"
#include "io/json_file.h"
#include "simulation/random.h"
#include "simulation/triad_log_simulator.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::CommandResult;
using testing::ExpectBadInputContract;
using testing::RunBinaryArgs;
using testing::ScratchDir;

// A triad in counts: 16-bit about mid-scale at 4061 counts per g (imu_tk's Xsens), or 12-bit for
// fewer counts per g; `noise_counts` of white noise, rounded to whole counts.
TriadLogSimulationOptions Sensor(double counts_per_g = 4061.0, double noise_counts = 3.0) {
  TriadLogSimulationOptions options;
  options.truth = counts_per_g < 2048.0 ? TriadParametersWithOffset(2071.0, 2012.0, 2090.0)
                                        : TriadParametersWithOffset(33124.2, 33275.2, 32364.4);
  for (int k = 0; k < 3; ++k) options.truth[kTriadGainX + k] = 9.81 / counts_per_g;
  options.noise_stddev = {noise_counts, noise_counts, noise_counts};
  return options;
}

// A session at 100 Hz: a rest of 10 s, then 30 poses of 3 s in random directions.
TriadLog SimulateSession(const TriadLogSimulationOptions& options, uint64_t seed) {
  RandomSource random(seed);
  std::vector<TriadHold> holds = {{{0.0, 0.0, 1.0}, 10.0}};
  for (const TriadHold& hold : RandomSeparatedHolds(30, 3.0, 30.0, &random)) holds.push_back(hold);
  return SimulateTriadSession(options, holds, &random).log;
}

// The log as a logger's CSV: t_s and three columns of `outputs` named ax, ay, az.
std::string Csv(const TriadLog& log, const std::vector<std::array<double, 3>>& outputs) {
  std::string text = "t_s,ax,ay,az\n";
  for (size_t i = 0; i < log.size(); ++i) {
    text += StringPrintf("%.2f,%.0f,%.0f,%.0f\n", log.timestamp_s[i], outputs[i][0], outputs[i][1],
                         outputs[i][2]);
  }
  return text;
}

CommandResult CalibrateMl(const std::string& log) {
  return RunBinaryArgs("calibrate_imu", {"--log=" + log, "--mode=ml", "--g=9.81"});
}

TEST(CauseMessages, TheSimulatedSessionItselfIsCalibrated) {
  ScratchDir scratch;
  const TriadLog log = SimulateSession(Sensor(), 1);
  const CommandResult result = CalibrateMl(scratch.Write("session.csv", Csv(log, log.output)));
  EXPECT_EQ(result.exit_status, 0) << result.stderr_text;
}

TEST(CauseMessages, ANumberBeyondADoubleIsNotFiniteRatherThanNotANumber) {
  ScratchDir scratch;
  std::string text = "t_s,ax,ay,az\n";
  for (int j = 0; j < 300; ++j)
    text += StringPrintf("%.2f,1,2,%s\n", 0.01 * j, j == 7 ? "1e999" : "9.8");
  const CommandResult result = CalibrateMl(scratch.Write("log.csv", text));
  ExpectBadInputContract(result, "calibrate_imu",
                         "line 9, column 'az' (az): '1e999' is not a finite number");
}

TEST(CauseMessages, AUtf16LogAndCrOnlyLineEndsAreSaid) {
  ScratchDir scratch;
  const std::string text = "t_s,ax,ay,az\n0.00,1,2,9.8\n0.01,1,2,9.8\n";
  std::string utf16 = "\xFF\xFE";
  for (const char c : text) utf16 += std::string(1, c) + '\0';
  const CommandResult result = CalibrateMl(scratch.Write("utf16.csv", utf16));
  ExpectBadInputContract(result, "calibrate_imu", "the file is UTF-16 text");
  EXPECT_NE(result.stderr_text.find("save or convert it as UTF-8"), std::string::npos)
      << result.stderr_text;
  std::string cr = text;
  std::replace(cr.begin(), cr.end(), '\n', '\r');
  ExpectBadInputContract(CalibrateMl(scratch.Write("cr.csv", cr)), "calibrate_imu",
                         "the lines end in a carriage return alone");
}

// Item 4 end to end: a 100 Hz session whose time column is the sample index.
TEST(CauseMessages, ASampleIndexAsTimeNamesRateHzAndTimeUnit) {
  ScratchDir scratch;
  TriadLog indexed = SimulateSession(Sensor(), 2);
  for (size_t i = 0; i < indexed.size(); ++i) indexed.timestamp_s[i] = static_cast<double>(i);
  const std::string log = scratch.Write("indexed.csv", Csv(indexed, indexed.output));
  const CommandResult result = CalibrateMl(log);
  ExpectBadInputContract(result, "calibrate_imu",
                         "time 't_s' counts 0, 1, 2, ... by 1: its name says seconds");
  EXPECT_NE(result.stderr_text.find("--rate_hz=R"), std::string::npos) << result.stderr_text;
  EXPECT_NE(result.stderr_text.find("--time_unit=s"), std::string::npos) << result.stderr_text;
  const CommandResult with_rate =
      RunBinaryArgs("calibrate_imu", {"--log=" + log, "--mode=ml", "--g=9.81", "--rate_hz=100"});
  EXPECT_EQ(with_rate.exit_status, 0) << with_rate.stderr_text;
}

TEST(CauseMessages, ATwoAxisCourseMatGivenToApplyWithATriadCalibrationIsSaid) {
  ACCELCAL_REQUIRE_COURSE_DATA(dir);
  ScratchDir scratch;
  std::string text;
  ASSERT_TRUE(JsonText(CalibrationJson(testing::ExampleTriadRecordWithGyroscope()), &text).ok());
  const std::string calibration = scratch.Write("triad.json", text);
  for (const char* file : {"acel.mat", "ensayo.mat"}) {
    SCOPED_TRACE(file);
    const CommandResult result =
        RunBinaryArgs("apply", {"--calibration=" + calibration, "--in=" + dir + "/" + file,
                                "--out=" + scratch.File("out.csv")});
    ExpectBadInputContract(result, "apply", "is the course's two-axis data");
    EXPECT_NE(result.stderr_text.find("the calibration is a triad's"), std::string::npos)
        << result.stderr_text;
  }
}

// A 12-bit triad (1024 counts per g) whose noise is below its resolution. With no noise at all,
// every pose sits on one level; with 0.2 count of noise under a slow wander of two counts (a
// drift of temperature or mount), the quietest windows' variances are a few level changes and
// the static detector refuses. Both refusals say the resolution.
TEST(CauseMessages, AQuantisedLogTheDetectorRefusesNamesTheResolution) {
  ScratchDir scratch;
  const TriadLog silent = SimulateSession(Sensor(1024.0, 0.0), 3);
  ExpectBadInputContract(CalibrateMl(scratch.Write("silent.csv", Csv(silent, silent.output))),
                         "calibrate_imu", "its noise is below the output's resolution");

  TriadLogSimulationOptions options = Sensor(1024.0, 0.2);
  options.round_to_counts = false;
  TriadLog log = SimulateSession(options, 3);
  for (size_t i = 0; i < log.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      log.output[i][k] =
          std::round(log.output[i][k] + 2.0 * std::sin(2.0 * M_PI * log.timestamp_s[i] / 5.0 + k));
    }
  }
  ExpectBadInputContract(CalibrateMl(scratch.Write("wandering.csv", Csv(log, log.output))),
                         "calibrate_imu",
                         "the output's resolution, steps of one count, dominates its noise");
}

TEST(CauseMessages, PosesWithAnAxisClippedAtFullScaleAreSaid) {
  ScratchDir scratch;
  const TriadLogSimulationOptions options = Sensor();
  const TriadLog log = SimulateSession(options, 4);
  // Full scale at 0.8 g above the offset on z: the poses with z near up read the maximum.
  std::vector<std::array<double, 3>> clipped = log.output;
  const double maximum = std::round(options.truth[kTriadOffsetZ] + 0.8 * 4061.0);
  for (std::array<double, 3>& u : clipped) u[2] = std::min(u[2], maximum);
  const CommandResult result = CalibrateMl(scratch.Write("clipped.csv", Csv(log, clipped)));
  ExpectBadInputContract(result, "calibrate_imu", "clipped samples");
  EXPECT_NE(result.stderr_text.find(StringPrintf("axis z sits at its maximum %.0f", maximum)),
            std::string::npos)
      << result.stderr_text;
}

// The gyroscope's columns of a simulated session, written as the accelerometer's.
TEST(CauseMessages, AGyroscopesLogGivenAsTheAccelerometersIsAskedAbout) {
  ScratchDir scratch;
  TriadLogSimulationOptions options = Sensor();
  options.gyroscope.enabled = true;
  const TriadLog log = SimulateSession(options, 5);
  ASSERT_TRUE(log.has_gyroscope());
  const CommandResult result = CalibrateMl(scratch.Write("gyroscope.csv", Csv(log, log.gyroscope)));
  ExpectBadInputContract(result, "calibrate_imu", "is this a gyroscope's log");
}

}  // namespace
}  // namespace accelcal
