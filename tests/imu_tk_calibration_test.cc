// imu_tk's accelerometer calibration (estimation/triad/imu_tk_calibration.h) against what imu_tk
// printed on its own Xsens log (issue 20), and on simulated triads whose truth is known.

#include "estimation/triad/imu_tk_calibration.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include "ceres/jet.h"
#include "common/format.h"
#include "io/imu_log.h"
#include "models/triad.h"
#include "simulation/triad_log_simulator.h"
#include "test_support.h"

namespace accelcal {
namespace {

// `value` written with as many significant digits as `printed` has, as imu_tk's stream did.
std::string ToPrintedDigits(double value, const std::string& printed) {
  int digits = 0;
  bool leading = true;
  for (const char c : printed) {
    if (c < '0' || c > '9') continue;
    if (leading && c == '0') continue;
    leading = false;
    ++digits;
  }
  return StringPrintf("%.*g", digits, value);
}

ImuTkOptions XsensOptions() {
  ImuTkOptions options;  // imu_tk's test application on its Xsens log
  options.gravity_mps2 = 9.81744;
  options.init_rest_s = 50.0;
  options.initial = TriadParametersWithOffset(32768.0, 32768.0, 32768.0);
  return options;
}

class ImuTkXsens : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::string dir = testing::ImuTkDataDir();
    if (dir.empty()) return;
    log_ = new TriadLog;
    result_ = new ImuTkResult;
    read_ = ReadImuLog(dir + "/xsens_acc.mat", log_);
    if (read_.ok()) solved_ = CalibrateImuTk(*log_, XsensOptions(), result_);
  }
  static void TearDownTestSuite() {
    delete log_;
    delete result_;
  }
  void SetUp() override {
    if (log_ == nullptr) {
      GTEST_SKIP() << "imu_tk data not found: set ACCELCAL_IMU_TK_DATA or put it in "
                      "../shared/data/imu_tk-xsens";
    }
    ASSERT_TRUE(read_.ok()) << read_.message();
    ASSERT_TRUE(solved_.ok()) << solved_.message();
  }
  static TriadLog* log_;
  static ImuTkResult* result_;
  static Status read_;
  static Status solved_;
};
TriadLog* ImuTkXsens::log_ = nullptr;
ImuTkResult* ImuTkXsens::result_ = nullptr;
Status ImuTkXsens::read_;
Status ImuTkXsens::solved_;

TEST_F(ImuTkXsens, ReadsEveryRowOfTheLog) {
  ASSERT_EQ(log_->size(), 51175u);
  EXPECT_DOUBLE_EQ(log_->timestamp_s.front(), 0.02984);
  EXPECT_DOUBLE_EQ(log_->output.front()[2], 36429.0);
  EXPECT_DOUBLE_EQ(log_->timestamp_s.back(), 511.718);
  EXPECT_DOUBLE_EQ(log_->output.back()[0], 35290.0);
}

TEST_F(ImuTkXsens, TheInitialRestEndsAtTheSampleNearest50sAfterTheFirst) {
  const double target = log_->timestamp_s.front() + 50.0;
  const int end = result_->rest_end;
  EXPECT_LE(std::abs(log_->timestamp_s[end] - target),
            std::abs(log_->timestamp_s[end - 1] - target));
  EXPECT_LT(std::abs(log_->timestamp_s[end] - target),
            std::abs(log_->timestamp_s[end + 1] - target));
}

TEST_F(ImuTkXsens, ReproducesImuTksPrintedCostAndIntervalCountForEveryK) {
  const char* printed_costs[] = {"0.134724", "0.131345", "0.126126", "0.120558", "0.120131",
                                 "0.120586", "0.121338", "0.121422", "0.13824"};
  const int printed_intervals[] = {42, 40, 39, 38, 38, 38, 38, 38, 38};
  ASSERT_EQ(result_->sweep.size(), 9u);
  for (int j = 0; j < 9; ++j) {
    const ImuTkSweepEntry& entry = result_->sweep[j];
    EXPECT_EQ(entry.multiplier, j + 2);
    EXPECT_TRUE(entry.solved) << "k = " << entry.multiplier;
    EXPECT_EQ(entry.used_intervals, printed_intervals[j]) << "k = " << entry.multiplier;
    EXPECT_EQ(StringPrintf("%g", entry.cost), printed_costs[j]) << "k = " << entry.multiplier;
  }
}

TEST_F(ImuTkXsens, ChoosesK6WithImuTksPrintedParameters) {
  const ImuTkSweepEntry& best = result_->best();
  EXPECT_EQ(best.multiplier, 6);
  const TriadParameters& p = best.parameters;
  EXPECT_EQ(ToPrintedDigits(p[kTriadMisalignmentYz], "0.0033593"), "0.0033593");
  EXPECT_EQ(ToPrintedDigits(p[kTriadMisalignmentZy], "-0.0089064"), "-0.0089064");
  EXPECT_EQ(ToPrintedDigits(p[kTriadMisalignmentZx], "0.0213341"), "0.0213341");
  EXPECT_EQ(StringPrintf("%g", 1.0 / p[kTriadGainX]), "414.459");
  EXPECT_EQ(StringPrintf("%g", 1.0 / p[kTriadGainY]), "412.01");
  EXPECT_EQ(StringPrintf("%g", 1.0 / p[kTriadGainZ]), "414.649");
  EXPECT_EQ(StringPrintf("%g", p[kTriadOffsetX]), "33124.2");
  EXPECT_EQ(StringPrintf("%g", p[kTriadOffsetY]), "33275.2");
  EXPECT_EQ(StringPrintf("%g", p[kTriadOffsetZ]), "32364.4");
}

TEST_F(ImuTkXsens, ReportsTheIntervalsOfTheChosenK) {
  ASSERT_EQ(result_->intervals.size(), 38u);
  // The log starts at rest: the first interval starts at the first classified sample.
  EXPECT_EQ(result_->intervals.front().start, 50);
  for (size_t i = 0; i < result_->intervals.size(); ++i) {
    const StaticInterval& s = result_->intervals[i];
    EXPECT_TRUE(result_->interval_used[i]);
    EXPECT_GE(s.sample_count(), 100);
    if (i > 0) EXPECT_GT(s.start, result_->intervals[i - 1].end + 1);
    // Held still: a few counts of noise, far below a pose's 4000-count gravity.
    for (int k = 0; k < 3; ++k) EXPECT_LT(s.noise_stddev[k], 10.0);
  }
}

// A triad close to the Xsens unit, to simulate from.
TriadParameters SimulatedTruth() {
  TriadParameters truth{};
  truth[kTriadMisalignmentYz] = 0.004;
  truth[kTriadMisalignmentZy] = -0.006;
  truth[kTriadMisalignmentZx] = 0.012;
  truth[kTriadGainX] = 1.0 / 410.0;
  truth[kTriadGainY] = 1.0 / 415.0;
  truth[kTriadGainZ] = 1.0 / 420.0;
  truth[kTriadOffsetX] = 33000.0;
  truth[kTriadOffsetY] = 33300.0;
  truth[kTriadOffsetZ] = 32400.0;
  return truth;
}

// Gravity directions spread over the sphere (a Fibonacci lattice), `count` of them.
std::vector<std::array<double, 3>> PoseDirections(int count) {
  std::vector<std::array<double, 3>> directions;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / count;
    const double r = std::sqrt(1.0 - z * z);
    directions.push_back({r * std::cos(golden * i), r * std::sin(golden * i), z});
  }
  return directions;
}

std::array<double, 3> RawAt(const TriadParameters& truth, const std::array<double, 3>& direction,
                            double g) {
  const double force[3] = {g * direction[0], g * direction[1], g * direction[2]};
  std::array<double, 3> raw;
  TriadRawOutput(truth.data(), force, raw.data());
  return raw;
}

TEST(TriadModel, RawOutputInvertsTheSpecificForce) {
  const TriadParameters truth = SimulatedTruth();
  const double force[3] = {3.0, -7.5, 5.25};
  double raw[3];
  TriadRawOutput(truth.data(), force, raw);
  double back[3];
  TriadSpecificForce(truth.data(), raw, back);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], force[k], 1e-12);
}

TEST(TriadModel, CompilesForCeresJets) {
  using Jet = ceres::Jet<double, kTriadParameterCount>;
  const TriadParameters truth = SimulatedTruth();
  Jet parameters[kTriadParameterCount];
  for (int p = 0; p < kTriadParameterCount; ++p) parameters[p] = Jet(truth[p], p);
  const double raw[3] = {33500.0, 32000.0, 36000.0};
  Jet force[3];
  TriadSpecificForce(parameters, raw, force);
  // d a_z / d gain_z = u_z - b_z.
  EXPECT_DOUBLE_EQ(force[2].v[kTriadGainZ], raw[2] - truth[kTriadOffsetZ]);
  EXPECT_DOUBLE_EQ(force[2].v[kTriadOffsetZ], -truth[kTriadGainZ]);
}

TEST(ImuTkCalibration, RecoversANoiseFreeTriadExactly) {
  const TriadParameters truth = SimulatedTruth();
  const double g = 9.81744;
  TriadLog log;
  std::vector<int> samples;
  for (const auto& direction : PoseDirections(20)) {
    samples.push_back(static_cast<int>(log.size()));
    const std::array<double, 3> raw = RawAt(truth, direction, g);
    log.Add(0.01 * log.size(), raw[0], raw[1], raw[2]);
  }
  ImuTkOptions options = XsensOptions();
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.max_iterations = 200;
  const ImuTkSweepEntry entry = SolveImuTkProblem(log, samples, options, nullptr);
  EXPECT_LT(entry.cost, 1e-20);
  for (int p = 0; p < kTriadParameterCount; ++p) {
    EXPECT_NEAR(entry.parameters[p], truth[p], 1e-9 * std::max(1.0, std::abs(truth[p])))
        << TriadParameterInfos()[p].name;
  }
}

// The whole rule on a simulated session: a rest, then poses held for 3 s, with rotations of
// 1.5 s between them and white noise of 3 counts, as in the Xsens log.
TEST(ImuTkCalibration, FindsThePosesOfASimulatedSessionAndRecoversTheTriad) {
  const TriadParameters truth = SimulatedTruth();
  const double g = 9.81744;
  std::mt19937_64 random(7);
  std::normal_distribution<double> noise(0.0, 3.0);
  TriadLog log;
  auto add = [&](const std::array<double, 3>& direction) {
    const std::array<double, 3> raw = RawAt(truth, direction, g);
    log.Add(0.01 * (log.size() + 1), raw[0] + noise(random), raw[1] + noise(random),
            raw[2] + noise(random));
  };
  const std::vector<std::array<double, 3>> poses = PoseDirections(24);
  for (int i = 0; i < 5000; ++i) add(poses[0]);
  for (size_t pose = 1; pose < poses.size(); ++pose) {
    for (int i = 0; i < 150; ++i) {  // rotate from the previous pose, along the great circle
      const double s = (i + 1) / 151.0;
      std::array<double, 3> d;
      for (int k = 0; k < 3; ++k) d[k] = (1 - s) * poses[pose - 1][k] + s * poses[pose][k];
      const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      add({d[0] / n, d[1] / n, d[2] / n});
    }
    for (int i = 0; i < 300; ++i) add(poses[pose]);
  }
  ImuTkResult result;
  const Status status = CalibrateImuTk(log, XsensOptions(), &result);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(result.best().used_intervals, 24);
  const TriadParameters& p = result.best().parameters;
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(p[kTriadMisalignmentYz + k], truth[kTriadMisalignmentYz + k], 5e-4);
    EXPECT_NEAR(p[kTriadGainX + k] / truth[kTriadGainX + k], 1.0, 5e-4);
    EXPECT_NEAR(p[kTriadOffsetX + k], truth[kTriadOffsetX + k], 2.0);
  }
}

TEST(ImuTkCalibration, RefusesASessionWithTooFewPoses) {
  TriadLog log;
  std::mt19937_64 random(3);
  std::normal_distribution<double> noise(0.0, 3.0);
  for (int i = 0; i < 8000; ++i)
    log.Add(0.01 * (i + 1), 33000 + noise(random), 33300 + noise(random), 36400 + noise(random));
  ImuTkResult result;
  const Status status = CalibrateImuTk(log, XsensOptions(), &result);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("finds 12 static intervals"), std::string::npos)
      << status.message();
}

// A sensor turning steadily from the first sample (0.7 and 0.31 rad/s, 1 m/s^2 of shake):
// every window is as quiet as the "rest"'s, yet the rest as a whole spans much of the sphere.
// Refused as a rest that drifts, not with a time the sensor starts moving (once "the sensor
// moves from t = 299.99 s", the log's end).
TEST(ImuTkCalibration, RefusesARestTheSensorTurnsSlowlyThrough) {
  TriadLogSimulationOptions simulation;
  simulation.truth = TriadParametersWithOffset(33124.2, 33275.2, 32364.4);
  for (int k = 0; k < 3; ++k) simulation.truth[kTriadGainX + k] = 1.0 / 414.5;
  simulation.gravity_mps2 = 9.81744;
  simulation.round_to_counts = false;
  RandomSource random(4);
  const TriadLog log = SimulateSteadyTurn(simulation, 300.0, 0.7, 0.31, 1.0, &random);
  ImuTkOptions options = XsensOptions();
  options.init_rest_s = 9.0;
  ImuTkResult result;
  const Status status = CalibrateImuTk(log, options, &result);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("drifts"), std::string::npos) << status.message();
  EXPECT_EQ(status.message().find("moves from"), std::string::npos) << status.message();
}

// A session whose rest lasts `rest_s`, then 16 poses of 4 s with turns of 1.5 s, at `rate_hz`,
// 3 counts of noise (SimulateTriadSession: the turns start and end slowly, as a hand's do).
// Over the last `creep_s` of the rest the output creeps by 6 counts/s on every axis and stays
// where it got to (the hand starts to tilt the sensor before turning it: each 1 s window adds
// 3 counts^2 to the noise's 9, below the check's limit of twice the median, while the rest as a
// whole varies far more). The first `cut_s` are dropped (0.75 s of a log without rest: it
// then starts mid-turn).
TriadLog RestThenPoses(double rest_s, double rate_hz, uint64_t seed, double creep_s = 0.0,
                       double cut_s = 0.0) {
  TriadLogSimulationOptions simulation;
  simulation.truth = TriadParametersWithOffset(33124.2, 33275.2, 32364.4);
  for (int k = 0; k < 3; ++k) simulation.truth[kTriadGainX + k] = 1.0 / 414.5;
  simulation.gravity_mps2 = 9.81744;
  simulation.rate_hz = rate_hz;
  RandomSource random(seed);
  const std::vector<std::array<double, 3>> directions = PoseDirections(17);
  std::vector<TriadHold> holds;
  for (size_t p = 0; p < directions.size(); ++p)
    holds.push_back({directions[p], p == 0 ? rest_s : 4.0});
  const TriadLog whole = SimulateTriadSession(simulation, holds, &random).log;
  TriadLog log;
  const double creep_start_s = rest_s - creep_s;
  for (size_t i = static_cast<size_t>(std::lround(cut_s * rate_hz)); i < whole.size(); ++i) {
    const double t_s = whole.timestamp_s[i];
    const double creep =
        creep_s > 0.0 ? 6.0 * creep_s * std::clamp((t_s - creep_start_s) / creep_s, 0.0, 1.0) : 0.0;
    log.Add(t_s, whole.output[i][0] + creep, whole.output[i][1] + creep,
            whole.output[i][2] + creep);
  }
  return log;
}

// The value of "--init_rest_s=V" in `message`, or a negative number when it suggests none.
double SuggestedRest(const std::string& message) {
  const std::string flag = "--init_rest_s=";
  const size_t at = message.find(flag);
  if (at == std::string::npos) return -1.0;
  return std::strtod(message.c_str() + at + flag.size(), nullptr);
}

// Issue 30, item 3: every "give --init_rest_s=V" of the rest check is followed, as a user
// would, by parsing V from the message and running again; the outcome must be a success or a
// different refusal, never the same advice again (once: "moves from t = 25.0077 s; give 25 or
// less", and with 25 the same; or 50 -> "give 6", 6 -> "give 0 or less" for motion at 5.3 s).
// Before the fix the 5.3 s rest's first suggestion, 5, was itself refused with "give 4 or less".
TEST(ImuTkCalibration, EverySuggestedInitialRestIsAcceptedByTheRestCheck) {
  struct Case {
    double rest_s;
    double creep_s;  // the rest's still part ends creep_s before rest_s
    double rate_hz;
    double init_rest_s;
  };
  for (const Case& c : {Case{5.3, 0.0, 100.0, 50.0}, Case{5.3, 3.0, 100.0, 50.0},
                        Case{5.3, 3.0, 100.0, 6.0}, Case{25.0077, 5.0, 62.5, 50.0},
                        Case{25.0077, 0.0, 62.5, 25.0}, Case{2.5, 0.0, 100.0, 30.0}}) {
    const TriadLog log = RestThenPoses(c.rest_s, c.rate_hz, 5, c.creep_s);
    ImuTkOptions options = XsensOptions();
    options.init_rest_s = c.init_rest_s;
    ImuTkResult result;
    Status status = CalibrateImuTk(log, options, &result);
    std::string previous;
    int suggestions = 0;
    while (!status.ok() && SuggestedRest(status.message()) > 0.0) {
      std::printf("[ advice    ] %s\n", status.message().c_str());
      ASSERT_LT(++suggestions, 3) << status.message();
      EXPECT_NE(status.message(), previous);
      previous = status.message();
      options.init_rest_s = SuggestedRest(status.message());
      // The suggestion ends near where the rest stops being still: the check tolerates the
      // first tenths of a second of a turn that starts slowly, and a part of the creep.
      EXPECT_LE(options.init_rest_s, c.rest_s + 0.2) << status.message();
      EXPECT_GE(options.init_rest_s, c.rest_s - c.creep_s - 0.5) << status.message();
      status = CalibrateImuTk(log, options, &result);
      EXPECT_EQ(status.message().find("is not at rest"), std::string::npos)
          << "rest " << c.rest_s << " s, suggested " << options.init_rest_s
          << " s refused again: " << status.message();
    }
    EXPECT_GE(suggestions, c.init_rest_s > c.rest_s ? 1 : 0) << c.rest_s;
    if (!status.ok()) std::printf("[ then      ] %s\n", status.message().c_str());
  }
}

// A log that moves within its first window has no rest to suggest: the message says so and
// names the detector that needs none, instead of "give --init_rest_s=0 or less".
TEST(ImuTkCalibration, SaysNoRestPassesWhenTheLogMovesAtOnce) {
  const TriadLog log = RestThenPoses(0.0, 100.0, 6, 0.0, 0.75);
  ImuTkOptions options = XsensOptions();
  options.init_rest_s = 6.0;
  ImuTkResult result;
  const Status status = CalibrateImuTk(log, options, &result);
  ASSERT_FALSE(status.ok());
  EXPECT_LT(SuggestedRest(status.message()), 0.0) << status.message();
  EXPECT_NE(status.message().find("no initial rest of this log passes"), std::string::npos)
      << status.message();
  EXPECT_NE(status.message().find("noise-floor detector"), std::string::npos) << status.message();
  // A rest shorter than one window: the suggested minimum holds one window.
  options.init_rest_s = 0.3;
  const Status too_short = CalibrateImuTk(RestThenPoses(8.0, 100.0, 7), options, &result);
  ASSERT_FALSE(too_short.ok());
  ASSERT_GT(SuggestedRest(too_short.message()), 0.0) << too_short.message();
  options.init_rest_s = SuggestedRest(too_short.message());
  const Status again = CalibrateImuTk(RestThenPoses(8.0, 100.0, 7), options, &result);
  EXPECT_EQ(again.message().find("fewer than the static detector's window"), std::string::npos)
      << again.message();
}

}  // namespace
}  // namespace accelcal
