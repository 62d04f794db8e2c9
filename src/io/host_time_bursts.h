#ifndef ACCELCAL_IO_HOST_TIME_BURSTS_H_
#define ACCELCAL_IO_HOST_TIME_BURSTS_H_

// Whether a log's time stamps are a host's receive times in bursts rather than the samples'
// times. A BLE, USB or serial link buffers the samples and delivers them a few at a time: the
// host stamps 2 to 20 samples within a fraction of a millisecond, then nothing for one or more
// sample periods (a BLE log: 0.2 ms apart, then 40 ms). Used as sample times, such stamps give
// most samples a step near zero and a few a step of several periods; the mean and variance of a
// pose survive, but anything that integrates over time (a gyroscope's turns, Allan's clusters)
// weighs each sample by a wrong step (issue 44: a turns chi2 of 85,533 against 24,017).
//
// The median step is no yardstick here: with bursts of 3 or more it is the within-burst step,
// with bursts of 2 it is either. The yardstick is the typical sample period, the median over
// blocks of kBlockSteps consecutive steps of their mean step: each block spans several bursts,
// so its mean is the period, and the median over blocks leaves out the few that hold a pause.
// Relative to it, a burst log has a large share of steps far below one period (within a burst)
// and a share far above it (the gaps that make up for them); an evenly sampled log, jitter and
// lost samples included, has almost no step below a third of the period:
//
//   bursty  <=>  share(step < period / 3) >= 20%  and  share(step > 1.5 period) >= 1%.
//
// A stamp late by 0.8 periods once in seven samples (a share of 14% below a third) passes, as
// host jitter; bursts of 2 (50% below), of 3 to 20 (67% to 95%) do not. The second condition
// keeps a change of rate (short steps not paid for by long ones) for the even-spacing check,
// which names it.
//
// The statistics are gathered in one pass with bounded memory (a streamed log of any size):
// steps and block means are counted in bins 0.1% wide on a log scale, so the shares and the
// median step are exact to that width.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace accelcal {

struct HostTimeBursts {
  size_t steps = 0;
  double period_s = 0.0;       // the typical sample period (median of the blocks' mean steps)
  double median_step_s = 0.0;  // to the bins' 0.1%
  double mean_step_s = 0.0;    // (last - first) / steps
  double short_share = 0.0;    // of steps below period / 3
  double long_share = 0.0;     // of steps above 1.5 periods
  bool bursty = false;
  double mean_rate_hz() const { return mean_step_s > 0.0 ? 1.0 / mean_step_s : 0.0; }
};

// Fed the time stamps one by one, in the log's order (increasing).
class HostTimeBurstTally {
 public:
  HostTimeBurstTally();
  void Add(double t_s);
  HostTimeBursts Result() const;

 private:
  size_t Bin(double step_s) const;
  double BinValue(size_t bin) const;

  std::vector<uint64_t> step_bins_;
  std::vector<uint64_t> block_bins_;
  size_t samples_ = 0;
  double first_t_s_ = 0.0;
  double previous_t_s_ = 0.0;
  double block_start_s_ = 0.0;
  size_t block_steps_ = 0;
};

HostTimeBursts MeasureHostTimeBursts(const std::vector<double>& timestamp_s);

// The statistics in words for a message: "62% of the steps below a third of the sample period
// of 10 ms and 38% above 1.5 periods; a median step of 0.2 ms, a mean of 10 ms (100 Hz)".
std::string DescribeHostTimeBursts(const HostTimeBursts& bursts);

}  // namespace accelcal

#endif  // ACCELCAL_IO_HOST_TIME_BURSTS_H_
