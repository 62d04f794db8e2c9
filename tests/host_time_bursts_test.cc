// Host receive times in bursts (issue 44, item 4): the detector (io/host_time_bursts.h) on
// BLE-like logs and on evenly sampled ones with jitter and lost samples, the device clock fitted
// to a sample-number column (io/index_clock_fit.h), and the reader (io/imu_log.h) that refuses
// such stamps as sample times, or times the samples by the index at the fitted rate.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "common/format.h"
#include "host_burst_log.h"
#include "io/host_time_bursts.h"
#include "io/imu_log.h"
#include "io/index_clock_fit.h"
#include "test_support.h"

namespace accelcal {
namespace {

using testing::HostBurstTimes;
using testing::JitteredStamps;
using testing::SimulateHostBursts;

std::vector<double> Seconds(const std::vector<long long>& stamps_us) {
  std::vector<double> seconds;
  for (long long t_us : stamps_us) seconds.push_back(1e-6 * static_cast<double>(t_us));
  return seconds;
}

TEST(HostTimeBursts, EveryBleLikeLogIsFound) {
  const double rates_hz[] = {50.0, 100.0, 104.0, 200.0, 400.0};
  int found = 0;
  for (unsigned seed = 0; seed < 200; ++seed) {
    const HostBurstTimes times =
        SimulateHostBursts(2000 + 40 * seed, rates_hz[seed % 5], 200.0, seed % 6, seed);
    found += MeasureHostTimeBursts(Seconds(times.host_us)).bursty ? 1 : 0;
  }
  std::cout << "BLE-like logs (bursts of 2 to 20) found bursty: " << found << " of 200\n";
  EXPECT_EQ(found, 200);
  // Every burst size alone, the hardest ends included: pairs, and bursts of 20.
  for (int size = 2; size <= 20; ++size) {
    const HostBurstTimes times = SimulateHostBursts(3000, 100.0, 0.0, 0, 7, size, size);
    const HostTimeBursts bursts = MeasureHostTimeBursts(Seconds(times.host_us));
    EXPECT_TRUE(bursts.bursty) << "bursts of " << size << ": " << DescribeHostTimeBursts(bursts);
  }
}

TEST(HostTimeBursts, NoFalseAlarmOnEvenLogsWithJitterAndLostSamples) {
  std::mt19937 random(44);
  std::uniform_real_distribution<double> log_rate(std::log(20.0), std::log(2000.0));
  std::uniform_real_distribution<double> jitter(0.0, 0.1);  // periods, per stamp
  std::uniform_int_distribution<int> dropped(0, 5);
  std::uniform_int_distribution<int> samples(300, 20000);
  int alarms = 0;
  double largest_short_share = 0.0;
  for (unsigned seed = 0; seed < 200; ++seed) {
    const std::vector<long long> stamps = JitteredStamps(
        samples(random), std::exp(log_rate(random)), jitter(random), dropped(random), seed);
    const HostTimeBursts bursts = MeasureHostTimeBursts(Seconds(stamps));
    alarms += bursts.bursty ? 1 : 0;
    largest_short_share = std::max(largest_short_share, bursts.short_share);
  }
  std::cout << "jittered even logs (20 Hz to 2 kHz, jitter up to 0.1 period, 0 to 5 lost) found "
               "bursty: "
            << alarms << " of 200; largest share of short steps " << largest_short_share << "\n";
  EXPECT_EQ(alarms, 0);
  // A stamp late by 0.8 periods once in seven samples, and a long pause: host jitter and a gap,
  // not bursts (the even-spacing check names the gap).
  std::vector<double> bunched;
  double t_s = 0.0;
  for (int j = 0; j < 1000; ++j) {
    bunched.push_back(t_s);
    t_s += j % 7 == 3 ? 0.002 : j % 7 == 4 ? 0.018 : j == 500 ? 3600.0 : 0.01;
  }
  EXPECT_FALSE(MeasureHostTimeBursts(bunched).bursty);
}

TEST(IndexClockFit, RecoversTheDeviceRateAndCountsTheLostSamples) {
  // Ten minutes at 100 Hz, the device 200 ppm fast, 7 samples lost.
  const HostBurstTimes times = SimulateHostBursts(60000, 100.0, 200.0, 7, 3);
  std::vector<double> index(times.index.begin(), times.index.end());
  IndexClockFit fit;
  std::vector<double> timestamp_s;
  ASSERT_TRUE(FitIndexClock(index, Seconds(times.host_us), &fit, &timestamp_s).ok());
  const double true_rate_hz = 100.0 * (1.0 + 200e-6);
  std::cout << "clock: " << DescribeIndexClockFit(fit) << "; truth " << true_rate_hz << " Hz\n";
  EXPECT_LE(std::abs(fit.rate_hz - true_rate_hz), fit.rate_tolerance_hz);
  EXPECT_LT(fit.rate_tolerance_hz, 2e-3);  // 20 ppm: the drift is told from none
  EXPECT_EQ(fit.nominal_rate_hz, 100.0);
  EXPECT_NEAR(fit.clock_drift_ppm, 200.0, 1e6 * fit.rate_tolerance_hz / 100.0);
  EXPECT_EQ(fit.dropped_samples, 7);
  // The times are the device's, up to the least delay (0.1 ms and more): the steps exact.
  double largest_error_s = 0.0;
  for (size_t j = 0; j < timestamp_s.size(); ++j) {
    largest_error_s = std::max(
        largest_error_s, std::abs((timestamp_s[j] - timestamp_s[0]) -
                                  (times.true_s[j] - times.true_s[0])));
  }
  EXPECT_LT(largest_error_s, 2e-4);
}

TEST(IndexClockFit, RefusesAColumnThatDoesNotCountTheSamples) {
  IndexClockFit fit;
  std::vector<double> t;
  const std::vector<double> host = {0.0, 0.0002, 0.04, 0.0402};
  EXPECT_ERROR_CONTAINS(FitIndexClock({0, 1.5, 2, 3}, host, &fit, &t), "not a whole number");
  EXPECT_ERROR_CONTAINS(FitIndexClock({0, 2, 1, 3}, host, &fit, &t), "does not increase");
  EXPECT_ERROR_CONTAINS(FitIndexClock({0, 10, 20, 30}, host, &fit, &t),
                        "does not count these samples");
}

// A CSV of the simulated stamps: host_time_us, [idx,] ax, ay, az.
std::string BurstCsv(const HostBurstTimes& times, const char* index_name) {
  std::string text = std::string("host_time_us,") + (index_name ? index_name : "") +
                     (index_name ? "," : "") + "ax,ay,az\n";
  for (size_t j = 0; j < times.index.size(); ++j) {
    text += std::to_string(times.host_us[j]) + "," +
            (index_name ? std::to_string(times.index[j]) + "," : std::string()) + "0.1,0.2,9.8\n";
  }
  return text;
}

TEST(ImuLogHostBursts, RefusedWithoutAnIndexNamingTheRateThatTimesThem) {
  const HostBurstTimes times = SimulateHostBursts(3000, 100.0, 200.0, 3, 11);
  const std::string text = BurstCsv(times, nullptr);
  TriadLog log;
  const Status refused = ParseImuLog(text, ImuLogReadOptions(), &log, ImuLogSpacing::kAny);
  ASSERT_FALSE(refused.ok());
  const std::string& message = refused.message();
  std::cout << message << "\n";
  for (const char* fragment :
       {"time 'host_time_us': the time stamps come in bursts", "of the steps below a third",
        "a median step of", "a mean of", "--columns=index:NAME"})
    EXPECT_NE(message.find(fragment), std::string::npos) << fragment << "\n" << message;
  const size_t at = message.find("--rate_hz=");
  ASSERT_NE(at, std::string::npos) << message;
  ImuLogReadOptions followed;
  followed.rate_hz = std::stod(message.substr(at + 10));
  EXPECT_NEAR(followed.rate_hz, 100.0, 0.5);
  const Status read = ParseImuLog(text, followed, &log);
  EXPECT_TRUE(read.ok()) << read.message();
  EXPECT_EQ(log.size(), times.index.size());
}

TEST(ImuLogHostBursts, TimedByTheIndexAtAFittedRateAndSaidSo) {
  const HostBurstTimes times = SimulateHostBursts(20000, 100.0, 200.0, 3, 12);
  TriadLog log;
  ImuLogSource source;
  const Status read =
      ParseImuLog(BurstCsv(times, "idx"), ImuLogReadOptions(), &log, ImuLogSpacing::kEven, &source);
  ASSERT_TRUE(read.ok()) << read.message();
  const ImuLogTiming& timing = source.timing;
  EXPECT_TRUE(timing.rate_fitted);
  EXPECT_TRUE(timing.bursts.bursty);
  EXPECT_EQ(timing.from, "sample number and a fitted rate");
  EXPECT_EQ(timing.index_column, "'idx'");
  EXPECT_EQ(timing.dropped_samples, 3);
  EXPECT_LE(std::abs(timing.fit.rate_hz - 100.02), timing.fit.rate_tolerance_hz);
  ASSERT_FALSE(source.notes.empty());
  std::cout << "read: " << source.notes[0] << "\n";
  EXPECT_EQ(source.notes[0].rfind("time: host receive times in bursts in 'host_time_us' (", 0), 0u)
      << source.notes[0];
  EXPECT_NE(source.notes[0].find("sample times from the index 'idx' at a fitted 100.0"),
            std::string::npos)
      << source.notes[0];
  EXPECT_NE(source.notes[0].find("3 dropped samples"), std::string::npos) << source.notes[0];
  // Evenly spaced but for the lost samples' steps.
  for (size_t j = 1; j < log.size(); ++j) {
    const double steps = (log.timestamp_s[j] - log.timestamp_s[j - 1]) * timing.fit.rate_hz;
    EXPECT_NEAR(steps, static_cast<double>(times.index[j] - times.index[j - 1]), 1e-6);
  }
}

TEST(ImuLogHostBursts, ACounterNotNamedAsOneIsNamedWithColumns) {
  const HostBurstTimes times = SimulateHostBursts(3000, 100.0, 200.0, 0, 13);
  const std::string text = BurstCsv(times, "pkt");
  TriadLog log;
  EXPECT_ERROR_CONTAINS(ParseImuLog(text, ImuLogReadOptions(), &log), "--columns=index:NAME");
  ImuLogReadOptions named;
  named.columns = "index:pkt";
  ImuLogSource source;
  const Status read = ParseImuLog(text, named, &log, ImuLogSpacing::kEven, &source);
  EXPECT_TRUE(read.ok()) << read.message();
  EXPECT_TRUE(source.timing.rate_fitted);
}

TEST(ImuLogHostBursts, TheStatedRateTimesTheIndexAndCountsLostSamples) {
  const HostBurstTimes times = SimulateHostBursts(3000, 100.0, 200.0, 4, 14);
  ImuLogReadOptions options;
  options.rate_hz = 100.0;
  TriadLog log;
  ImuLogSource source;
  const Status read =
      ParseImuLog(BurstCsv(times, "idx"), options, &log, ImuLogSpacing::kEven, &source);
  ASSERT_TRUE(read.ok()) << read.message();
  EXPECT_FALSE(source.timing.rate_fitted);
  EXPECT_EQ(source.timing.from, "sample number and --rate_hz");
  EXPECT_EQ(source.timing.dropped_samples, 4);
  EXPECT_DOUBLE_EQ(log.timestamp_s.back(), times.index.back() / 100.0);
}

TEST(ImuLogHostBursts, StreamingFailsAsTheWholeReadDoesOrAsksForIt) {
  testing::ScratchDir scratch;
  const HostBurstTimes times = SimulateHostBursts(3000, 100.0, 200.0, 2, 15);
  const std::string plain = scratch.Write("plain.csv", BurstCsv(times, nullptr));
  TriadLog whole;
  const Status read = ReadImuLog(plain, ImuLogReadOptions(), &whole, ImuLogSpacing::kAny);
  ASSERT_FALSE(read.ok());
  size_t streamed = 0;
  const auto count = [&](const TriadLog& batch) { streamed += batch.size(); };
  ImuLogSource source;
  const Status stream = StreamImuLog(plain, ImuLogReadOptions(), 256, count, &source);
  EXPECT_EQ(stream.message(), read.message());
  EXPECT_FALSE(source.times_need_whole_log);
  const std::string indexed = scratch.Write("indexed.csv", BurstCsv(times, "idx"));
  EXPECT_FALSE(StreamImuLog(indexed, ImuLogReadOptions(), 256, count, &source).ok());
  EXPECT_TRUE(source.times_need_whole_log);
  ImuLogSource whole_source;
  EXPECT_TRUE(
      ReadImuLog(indexed, ImuLogReadOptions(), &whole, ImuLogSpacing::kEven, &whole_source).ok());
  EXPECT_TRUE(whole_source.timing.rate_fitted);
}

}  // namespace
}  // namespace accelcal
