// The noise-floor detector in passes over a log it does not hold
// (estimation/triad/noise_floor_stream.h, issue 36, item 2): on every log it decides, the whole-log
// detector's intervals, floors, thresholds and rule to the last bit, read from memory or from a
// temporary file (io/sample_spool.h); where the whole-log detector refuses, or takes the per-pose
// rule because the single floor refuses, it does not decide.

#include "estimation/triad/noise_floor_stream.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "estimation/triad/noise_floor_detector.h"
#include "estimation/triad/window_variance_stream.h"
#include "hand_held_session.h"
#include "io/imu_log.h"
#include "io/sample_spool.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::HandHeldSession;

void ExpectSameIntervals(const std::vector<StaticInterval>& a, const std::vector<StaticInterval>& b,
                         const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].start, b[i].start) << what << " " << i;
    EXPECT_EQ(a[i].end, b[i].end) << what << " " << i;
    EXPECT_EQ(a[i].start_s, b[i].start_s) << what << " " << i;
    EXPECT_EQ(a[i].end_s, b[i].end_s) << what << " " << i;
    EXPECT_EQ(a[i].duration_s, b[i].duration_s) << what << " " << i;
    EXPECT_EQ(a[i].mean, b[i].mean) << what << " " << i;
    EXPECT_EQ(a[i].noise_stddev, b[i].noise_stddev) << what << " " << i;
  }
}

// Every field the detection reports, compared exactly.
void ExpectSameDetection(const NoiseFloorDetection& whole, const NoiseFloorDetection& streamed) {
  EXPECT_EQ(whole.rule, streamed.rule);
  EXPECT_EQ(whole.rule_reason, streamed.rule_reason);
  EXPECT_EQ(whole.window_samples, streamed.window_samples);
  EXPECT_EQ(whole.floor_variance, streamed.floor_variance);
  EXPECT_EQ(whole.floor_stddev, streamed.floor_stddev);
  EXPECT_EQ(whole.threshold_variance, streamed.threshold_variance);
  EXPECT_EQ(whole.white_false_alarm, streamed.white_false_alarm);
  EXPECT_EQ(whole.still_fraction, streamed.still_fraction);
  EXPECT_EQ(whole.floor_shape, streamed.floor_shape);
  ExpectSameIntervals(whole.intervals, streamed.intervals, "intervals");
  ExpectSameIntervals(whole.short_intervals, streamed.short_intervals, "short");
  ExpectSameIntervals(whole.moving_intervals, streamed.moving_intervals, "moving");
}

// The streamed detection of `log` (from memory) against the whole-log detector's: the same when
// decided; returns whether it decided. Undecided only where the whole-log detector refuses or
// chose the per-pose rule because the single floor refused.
bool Compare(const TriadLog& log, const char* name, size_t max_run_windows = size_t{1} << 20) {
  NoiseFloorOptions options;
  options.min_intervals = 0;
  NoiseFloorDetection whole;
  const Status whole_status = DetectStaticIntervalsFromNoiseFloor(log, options, &whole);
  NoiseFloorStreamOptions stream_options;
  stream_options.detector = options;
  stream_options.max_run_windows = max_run_windows;
  NoiseFloorDetection streamed;
  bool decided = true;
  const Status status = DetectStaticIntervalsFromNoiseFloorStreamed(
      TriadLogSamples(log), stream_options, &streamed, &decided);
  EXPECT_TRUE(status.ok()) << name << ": " << status.message();
  std::printf("[ %-9s ] whole: %s, rule %s, %zu poses; streamed: %s\n", name,
              whole_status.ok() ? "accepted" : "refused", whole.rule.c_str(),
              whole.intervals.size(), decided ? "decided" : "not decided");
  if (decided) {
    EXPECT_TRUE(whole_status.ok()) << name << ": " << whole_status.message();
    ExpectSameDetection(whole, streamed);
  } else if (whole_status.ok() && max_run_windows >= log.size()) {
    EXPECT_EQ(whole.rule, kPoseFloorsRule) << name;
    EXPECT_EQ(whole.rule_reason.find("one noise floor for the log found"), std::string::npos)
        << name << ": the per-pose rule's reason is known, the streamed detector should decide";
  }
  return decided;
}

TEST(WindowVarianceStream, IsTheWholeLogsWindowVariances) {
  const TriadLog log = HandHeldSession(3, 6).log;
  for (const int window : {3, 11, 101}) {
    WindowVarianceStream stream(window);
    const std::vector<std::array<double, 3>> whole = WindowVariances(log, window);
    size_t j = 0;
    for (const std::array<double, 3>& output : log.output) {
      if (!stream.Add(output)) continue;
      ASSERT_LT(j, whole.size());
      EXPECT_EQ(stream.variance(), whole[j]) << "window " << window << ", j " << j;
      ++j;
    }
    EXPECT_EQ(j, whole.size());
  }
}

// White noise of 3 counts: the single floor; several seeds and lengths.
TEST(NoiseFloorStream, EqualsTheWholeLogDetectorOnWhiteNoiseSessions) {
  for (uint64_t seed = 1; seed <= 4; ++seed)
    EXPECT_TRUE(Compare(HandHeldSession(seed, 8 + 6 * static_cast<int>(seed)).log, "white"));
}

// Noise that differs fourfold between poses: the per-pose rule finds more poses than the
// single floor (which accepts), and is taken with its reason.
TEST(NoiseFloorStream, EqualsTheWholeLogDetectorWhereThePerPoseRuleFindsMore) {
  int pose_rule = 0;
  for (uint64_t seed = 101; seed <= 103; ++seed) {
    const TriadLog log = HandHeldSession(seed, 16, 1.5, /*fourfold=*/true).log;
    NoiseFloorDetection whole;
    NoiseFloorOptions options;
    options.min_intervals = 0;
    ASSERT_TRUE(DetectStaticIntervalsFromNoiseFloor(log, options, &whole).ok());
    pose_rule += whole.rule == kPoseFloorsRule ? 1 : 0;
    Compare(log, "per pose");
  }
  EXPECT_GT(pose_rule, 0) << "no session exercised the per-pose rule";
}

// Noise far below a count (quantised: the single floor refuses, the per-pose rule takes the
// poses and quotes the refusal) and a log that never rests (both refuse): not decided.
TEST(NoiseFloorStream, DoesNotDecideWhereTheWholeLogDetectorRefusesOrQuotesARefusal) {
  EXPECT_FALSE(Compare(HandHeldSession(41, 12, 0.0).log, "quantised"));
  const TriadLog moving = testing::NeverRestingLog(31);
  EXPECT_FALSE(Compare(moving, "moving"));
}

// Candidate runs longer than the run buffer (a still log of hours is one run of millions of
// windows): their floors from passes over their windows, the same detection to the last bit
// (issue 49, item 1), with the single floor and where the per-pose rule finds more.
TEST(NoiseFloorStream, RunsLongerThanTheBufferGiveTheSameDetection) {
  EXPECT_TRUE(Compare(HandHeldSession(2, 10).log, "long run", 50));
  EXPECT_TRUE(Compare(HandHeldSession(3, 14).log, "long run", 1));
  for (uint64_t seed = 101; seed <= 103; ++seed)
    Compare(HandHeldSession(seed, 16, 1.5, /*fourfold=*/true).log, "long pose", 50);
}

// Read back from the temporary file, the same detection as from memory.
TEST(NoiseFloorStream, FromASpooledLogEqualsFromMemory) {
  const TriadLog log = HandHeldSession(7, 14).log;
  SampleSpool spool;
  ASSERT_TRUE(spool.Open().ok());
  for (size_t i = 0; i < log.size(); ++i)
    ASSERT_TRUE(spool.Append(log.timestamp_s[i], log.output[i]).ok());
  ASSERT_TRUE(spool.Finish().ok());
  ASSERT_EQ(spool.size(), log.size());
  TriadLog back;
  ASSERT_TRUE(spool.Read(1234, 5000, &back).ok());
  for (size_t j = 0; j < back.size(); ++j) {
    EXPECT_EQ(back.timestamp_s[j], log.timestamp_s[1234 + j]);
    EXPECT_EQ(back.output[j], log.output[1234 + j]);
  }
  NoiseFloorStreamOptions options;
  options.detector.min_intervals = 0;
  NoiseFloorDetection from_memory, from_file;
  bool decided_memory = false, decided_file = false;
  ASSERT_TRUE(DetectStaticIntervalsFromNoiseFloorStreamed(TriadLogSamples(log), options,
                                                          &from_memory, &decided_memory)
                  .ok());
  ASSERT_TRUE(
      DetectStaticIntervalsFromNoiseFloorStreamed(spool, options, &from_file, &decided_file).ok());
  ASSERT_TRUE(decided_memory && decided_file);
  ExpectSameDetection(from_memory, from_file);
}

// imu_tk's Xsens log (a real sensor's noise, hand taps and all).
TEST(NoiseFloorStream, EqualsTheWholeLogDetectorOnTheXsensLog) {
  ACCELCAL_REQUIRE_IMU_TK_DATA(dir);
  TriadLog log;
  ASSERT_TRUE(ReadImuLog(dir + "/xsens_acc.mat", &log).ok());
  EXPECT_TRUE(Compare(log, "xsens"));
}

}  // namespace
}  // namespace accelcal
