#ifndef ACCELCAL_TESTS_HOST_BURST_LOG_H_
#define ACCELCAL_TESTS_HOST_BURST_LOG_H_

// Host receive times of a BLE-like link, for the tests of io/host_time_bursts.h and
// io/index_clock_fit.h (issue 44, item 4): the device samples at `rate_hz` on its own clock,
// which runs `drift_ppm` fast against the host's (sample i at i / (rate (1 + drift)) host
// seconds); the link delivers the samples in bursts of 2 to 20 (drawn uniformly) after the
// burst's last sample, 0.1 to 3 ms later, 0.2 ms apart; the host stamps them in whole
// microseconds. A few samples are lost in the link (their rows are missing, the index jumps).
// And, against them, evenly sampled host stamps with jitter and a few lost samples.

#include <cmath>
#include <random>
#include <set>
#include <vector>

namespace accelcal {
namespace testing {

struct HostBurstTimes {
  std::vector<long long> index;        // the rows kept: the device's sample numbers
  std::vector<double> true_s;          // their times on the device clock, in host seconds
  std::vector<long long> host_us;      // their receive times
  long long dropped = 0;
};

inline HostBurstTimes SimulateHostBursts(int samples, double rate_hz, double drift_ppm,
                                         int dropped, unsigned seed, int smallest_burst = 2,
                                         int largest_burst = 20) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> burst_size(smallest_burst, largest_burst);
  std::uniform_real_distribution<double> latency_s(1e-4, 3e-3);
  const double period_s = 1.0 / (rate_hz * (1.0 + 1e-6 * drift_ppm));
  std::set<int> lost;
  std::uniform_int_distribution<int> anywhere(1, samples - 2);
  while (static_cast<int>(lost.size()) < dropped) lost.insert(anywhere(random));
  HostBurstTimes times;
  times.dropped = dropped;
  const double host_origin_s = 5.0;  // the host's clock when the device starts
  for (int first = 0; first < samples;) {
    const int last = std::min(samples - 1, first + burst_size(random) - 1);
    const double delivered_s = host_origin_s + last * period_s + latency_s(random);
    for (int i = first, position = 0; i <= last; ++i) {
      if (lost.count(i)) continue;
      times.index.push_back(i);
      times.true_s.push_back(host_origin_s + i * period_s);
      times.host_us.push_back(std::llround((delivered_s + 2e-4 * position++) * 1e6));
    }
    first = last + 1;
  }
  return times;
}

// Evenly sampled stamps (in microseconds) at `rate_hz` with Gaussian jitter of `jitter`
// periods per stamp (kept increasing) and `dropped` samples lost.
inline std::vector<long long> JitteredStamps(int samples, double rate_hz, double jitter,
                                             int dropped, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0.0, jitter);
  std::uniform_int_distribution<int> anywhere(1, samples - 2);
  std::set<int> lost;
  while (static_cast<int>(lost.size()) < dropped) lost.insert(anywhere(random));
  std::vector<long long> stamps;
  for (int i = 0; i < samples; ++i) {
    if (lost.count(i)) continue;
    const long long t_us = std::llround((i + noise(random)) / rate_hz * 1e6);
    if (stamps.empty() || t_us > stamps.back()) stamps.push_back(t_us);
  }
  return stamps;
}

}  // namespace testing
}  // namespace accelcal

#endif  // ACCELCAL_TESTS_HOST_BURST_LOG_H_
