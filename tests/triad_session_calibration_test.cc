// One session's calibration (estimation/triad/triad_session_calibration.h), the sequence behind
// every calibrate_imu --mode=ml path: on imu_tk's Xsens log it reproduces what the CLI prints with
// the noise-floor detector (the default), with imu_tk's intervals (--detector=imu_tk), with
// --noise=white and with --scale_nonlinearity; and it refuses a log whose unit is misstated.

#include "estimation/triad/triad_session_calibration.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "common/format.h"
#include "estimation/triad/imu_tk_calibration.h"
#include "estimation/triad/noise_floor_detector.h"
#include "io/imu_log.h"
#include "models/triad_units.h"
#include "simulation/random.h"
#include "simulation/triad_log_simulator.h"
#include "simulation/triad_simulator.h"
#include "test_support.h"

namespace accelcal {
namespace {

// calibrate_imu --log=xsens_acc.mat --g=9.81744 --mode=ml's options (the flags' defaults).
TriadSessionOptions XsensOptions() {
  TriadSessionOptions options;
  options.gravity_mps2 = 9.81744;
  return options;
}

// imu_tk's intervals at its chosen k, the ones its cost used, as --detector=imu_tk takes them.
std::vector<StaticInterval> ImuTkIntervals(const TriadLog& log) {
  ImuTkOptions options;
  options.gravity_mps2 = 9.81744;
  options.init_rest_s = 50.0;
  options.initial = TriadParametersWithOffset(32768.0, 32768.0, 32768.0);  // auto: mid-scale
  ImuTkResult result;
  EXPECT_TRUE(CalibrateImuTk(log, options, &result).ok());
  std::vector<StaticInterval> used;
  for (size_t i = 0; i < result.intervals.size(); ++i) {
    if (result.interval_used[i]) used.push_back(result.intervals[i]);
  }
  return used;
}

// What `calibrate_imu --log=xsens_acc.mat --g=9.81744 --mode=ml` prints with the flags named
// (the same before and after this sequence was shared, 6d1a6bf).
struct Printed {
  const char* flags;
  bool imu_tk_detector;
  TriadNoiseChoice noise;
  bool scale_nonlinearity;
  int poses;
  int samples;
  double offset_x;
  double offset_x_stddev;
  double gain_y;
  double chi2;
  int dof;  // 3 fewer with --scale_nonlinearity
};

constexpr TriadNoiseChoice kAuto = TriadNoiseChoice::kAuto;
constexpr TriadNoiseChoice kWhite = TriadNoiseChoice::kWhite;
const Printed kPrinted[] = {
    {"", false, kAuto, false, 38, 32840, 33123.831, 0.221, 0.0024269976, 27.5893, 29},
    {"--detector=imu_tk", true, kAuto, false, 38, 32812, 33123.835, 0.221, 0.0024269977, 27.5616,
     29},
    {"--noise=white", false, kWhite, false, 38, 32840, 33123.822, 0.0766, 0.0024269376, 446.593,
     29},
    {"--scale_nonlinearity", false, kAuto, true, 38, 32840, 33124.11, 0.618, 0.0024269932, 25.4669,
     26},
    {"--scale_nonlinearity --detector=imu_tk --noise=white", true, kWhite, true, 38, 32812,
     33124.25, 0.175, 0.0024269481, 420.104, 26},
};

TEST(TriadSessionCalibration, ReproducesTheCliOnXsensWithEitherDetector) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  TriadLog log;
  ASSERT_TRUE(ReadImuLog(dir + "/xsens_acc.mat", &log).ok());
  const std::vector<StaticInterval> imu_tk_intervals = ImuTkIntervals(log);
  for (const Printed& printed : kPrinted) {
    SCOPED_TRACE(printed.flags);
    TriadSessionOptions options = XsensOptions();
    options.noise = printed.noise;
    options.scale_nonlinearity = printed.scale_nonlinearity;
    TriadSessionCalibration calibration;
    const Status status =
        printed.imu_tk_detector
            ? CalibrateTriadSessionOnIntervals(log, imu_tk_intervals, options, &calibration)
            : CalibrateTriadSession(log, options, &calibration);
    ASSERT_TRUE(status.ok()) << status.message();
    // The noise-floor path keeps its detection; imu_tk's intervals come with none.
    EXPECT_EQ(calibration.detection.intervals.size(), printed.imu_tk_detector ? 0u : 38u);
    const TriadMlResult& ml = calibration.ml;
    EXPECT_EQ(ml.pose_count, printed.poses);
    EXPECT_EQ(static_cast<int>(calibration.pose_intervals.size()), printed.poses);
    EXPECT_EQ(calibration.sample_count, printed.samples);
    // --noise=auto takes the Allan model on this log (white noise rejected, p = 6e-88).
    EXPECT_EQ(calibration.allan_noise, printed.noise == kAuto);
    EXPECT_EQ(ml.mean_stddev_from_caller, printed.noise == kAuto);
    EXPECT_NEAR(ml.parameters[kTriadOffsetX], printed.offset_x, 5e-4);
    EXPECT_NEAR(ml.stddev[kTriadOffsetX], printed.offset_x_stddev, 5e-4);
    EXPECT_NEAR(ml.parameters[kTriadGainY], printed.gain_y, 5e-11);
    EXPECT_NEAR(ml.chi2, printed.chi2, 5e-4);
    EXPECT_EQ(ml.degrees_of_freedom, printed.dof);
    // Discovery ran on the same poses: the Allan model found missing from the white one.
    EXPECT_EQ(calibration.discovery.verdict_code, Verdict::kMissing);
    EXPECT_EQ(calibration.discovery_options.alpha, 0.01);
  }
}

TEST(TriadSessionCalibration, RefusesALogWhoseUnitIsMisstated) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  TriadLog log;
  ASSERT_TRUE(ReadImuLog(dir + "/xsens_acc.mat", &log).ok());
  TriadSessionOptions options = XsensOptions();
  options.unit = TriadOutputUnit::kG;
  TriadSessionCalibration calibration;
  for (const bool given_intervals : {false, true}) {
    const Status status = given_intervals ? CalibrateTriadSessionOnIntervals(
                                                log, ImuTkIntervals(log), options, &calibration)
                                          : CalibrateTriadSession(log, options, &calibration);
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.message().find("not about 1 as 1 g is in g"), std::string::npos)
        << status.message();
  }
  // The start's offset of a log in counts: the 16-bit ADC's mid-scale, or the number given.
  double offset = 0.0;
  ASSERT_TRUE(TriadStartOffset(log, TriadOutputUnit::kCount, {}, &offset).ok());
  EXPECT_EQ(offset, 32768.0);
  ASSERT_TRUE(TriadStartOffset(log, TriadOutputUnit::kCount, {false, 33000.0}, &offset).ok());
  EXPECT_EQ(offset, 33000.0);
}

// Gains against the stated unit: all three near 1 (m/s^2)/count is a log already in m/s^2;
// one near 1 and the others a count's is an axis the poses left at its start (imu_tk's fit
// of poses in a plane), not a unit, and the refusal says so.
TEST(TriadUnits, TellsALogInAnotherUnitFromAGainThePosesDidNotDetermine) {
  TriadParameters counts = TriadParametersWithOffset(33000.0, 33000.0, 33000.0);
  for (int k = 0; k < 3; ++k) counts[kTriadGainX + k] = 1.0 / 415.0;
  EXPECT_TRUE(CheckGainsMatchUnit(counts, TriadOutputUnit::kCount).ok());
  TriadParameters converted = counts;
  for (int k = 0; k < 3; ++k) converted[kTriadGainX + k] = 1.001;
  Status status = CheckGainsMatchUnit(converted, TriadOutputUnit::kCount);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("already converted to m/s^2"), std::string::npos)
      << status.message();
  TriadParameters planar = counts;
  planar[kTriadGainY] = 0.992;
  status = CheckGainsMatchUnit(planar, TriadOutputUnit::kCount);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("do not determine the gains"), std::string::npos)
      << status.message();
  EXPECT_EQ(status.message().find("converted"), std::string::npos) << status.message();
}

// A session whose poses are 40 times noisier than others (the unit set down on a running
// machine between hand-held poses, and for its initial rest): the noise floor's detector, which
// takes poses within 16 times the quietest one's noise, finds too few; imu_tk's, scaled from the
// noisy rest, finds them all. The default then stands on imu_tk's intervals and says so, and
// the calibration recovers the truth; with no fallback the refusal gives both detectors' words.
TEST(TriadSessionCalibration, FallsBackOnImuTksIntervalsWhenTheNoiseFloorRefuses) {
  TriadLogSimulationOptions simulation;
  simulation.truth = TriadParametersWithOffset(33124.2, 33275.2, 32364.4);
  simulation.truth[kTriadMisalignmentYz] = 0.0033593;
  simulation.truth[kTriadGainX] = 1.0 / 414.459;
  simulation.truth[kTriadGainY] = 1.0 / 412.01;
  simulation.truth[kTriadGainZ] = 1.0 / 414.649;
  simulation.gravity_mps2 = 9.81744;
  RandomSource random(2026);
  std::vector<TriadHold> holds = {{{0.0, 0.0, 1.0}, 52.0, 40.0}};
  while (holds.size() < 24) {
    const std::array<double, 3> d = RandomPoseDirections(1, &random).front();
    const std::array<double, 3>& last = holds.back().direction;
    if (d[0] * last[0] + d[1] * last[1] + d[2] * last[2] > std::cos(40.0 * M_PI / 180.0)) continue;
    holds.push_back({d, 4.0, holds.size() % 3 == 0 ? 1.0 : 40.0});
  }
  const TriadLog log = SimulateTriadSession(simulation, holds, &random).log;
  TriadSessionOptions options = XsensOptions();
  NoiseFloorDetection detection;
  const Status detected = DetectStaticIntervalsFromNoiseFloor(log, options.detector, &detection);
  ASSERT_FALSE(detected.ok())
      << "the noise floor's detector must refuse this session for the test to mean anything";
  const std::string detection_message = detected.message();
  const std::vector<StaticInterval> imu_tk = ImuTkIntervals(log);
  ASSERT_GE(imu_tk.size(), 20u);

  TriadSessionCalibration calibration;
  std::string fallback_reason;
  const Status status =
      CalibrateTriadSessionWithFallback(log, options, &imu_tk, "", &calibration, &fallback_reason);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_FALSE(fallback_reason.empty());
  EXPECT_EQ(calibration.ml.pose_count, static_cast<int>(imu_tk.size()));
  for (int p : {kTriadGainX, kTriadGainY, kTriadGainZ, kTriadOffsetX, kTriadOffsetY, kTriadOffsetZ,
                kTriadMisalignmentYz}) {
    EXPECT_LT(std::abs(calibration.ml.parameters[p] - simulation.truth[p]),
              4.0 * calibration.ml.stddev[p])
        << TriadParameterInfos()[p].name;
  }

  // Neither detector: the noise floor's finding leads; imu_tk's refusal is one clause, without
  // its advice (an initial rest that would be refused again).
  const std::string imu_tk_refusal =
      "the initial rest of 50 s is not at rest: its variance norm is 1.7e+03 times the median of "
      "its windows (at most 2 when still), and the sensor moves from t = 1.5 s; give "
      "--init_rest_s=1.48, the longest initial rest before the motion that this check accepts";
  const Status refused = CalibrateTriadSessionWithFallback(log, options, nullptr, imu_tk_refusal,
                                                           &calibration, &fallback_reason);
  ASSERT_FALSE(refused.ok());
  const std::string& message = refused.message();
  EXPECT_EQ(message.rfind(
                "no static detector finds the poses: the noise floor's: " + detection_message, 0),
            0u)
      << message;
  EXPECT_NE(message.find("imu_tk's intervals, the fallback, give none either (the initial rest "
                         "of 50 s is not at rest)"),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find("--init_rest_s"), std::string::npos) << message;
  EXPECT_LE(message.size(), 520u) << message;
}

// The probe's session (holds of 1 to 1.5 s at 100 Hz, no initial rest): its refusal once passed
// 600 bytes and lost the noise floor's advice in calibrate_imu's cut. Now it names a window that
// works, and stays short with a long imu_tk refusal.
TEST(TriadSessionCalibration, RefusalOfBothDetectorsLeadsWithAWindowThatWorks) {
  TriadLogSimulationOptions simulation;
  simulation.truth = TriadParametersWithOffset(84.0, 8.0, 62.0);
  for (int k = 0; k < 3; ++k) simulation.truth[kTriadGainX + k] = 9.81 / 8192.0;
  RandomSource random(2027);
  std::vector<TriadHold> holds = RandomSeparatedHolds(30, 1.0, 30.0, &random);
  for (size_t i = 0; i < holds.size(); ++i) holds[i].duration_s = 1.0 + 0.1 * (i % 6);
  const TriadLog log = SimulateTriadSession(simulation, holds, &random).log;
  TriadSessionOptions options;
  options.gravity_mps2 = 9.81;
  TriadSessionCalibration calibration;
  std::string fallback_reason;
  const Status refused = CalibrateTriadSessionWithFallback(
      log, options, nullptr, std::string(400, 'x') + ": and more", &calibration, &fallback_reason);
  ASSERT_FALSE(refused.ok());
  const std::string& message = refused.message();
  EXPECT_LE(message.size(), 520u) << message;
  const NoiseFloorDetection& d = calibration.detection;
  ASSERT_GT(d.suggested_window_samples, 0) << message;
  EXPECT_NE(message.find(StringPrintf("--window=%d --min_interval_s=%g finds %d",
                                      d.suggested_window_samples, d.suggested_min_interval_s,
                                      d.suggested_pose_count)),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find("noise-floor detector"), std::string::npos) << message;
  options.detector.window_samples = d.suggested_window_samples;
  options.detector.min_interval_s = d.suggested_min_interval_s;
  const Status followed =
      CalibrateTriadSessionWithFallback(log, options, nullptr, "", &calibration, &fallback_reason);
  ASSERT_TRUE(followed.ok()) << followed.message();
  EXPECT_GE(calibration.ml.pose_count, 27);
}

}  // namespace
}  // namespace accelcal
