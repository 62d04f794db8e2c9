#include "io/host_time_bursts.h"

#include <algorithm>
#include <cmath>

#include "common/format.h"

namespace accelcal {
namespace {

// Blocks of this many steps give the period: several bursts of up to 20 samples each.
constexpr size_t kBlockSteps = 64;
constexpr double kShortStepPeriods = 1.0 / 3.0;
constexpr double kLongStepPeriods = 1.5;
constexpr double kMinShortShare = 0.20;
constexpr double kMinLongShare = 0.01;
// Fewer steps tell nothing of a pattern.
constexpr size_t kMinSteps = 16;

// The bins: 0.1% wide from 1 ns to 1e5 s (steps outside fall in the end bins).
constexpr double kLowestStepS = 1e-9;
constexpr double kHighestStepS = 1e5;
constexpr double kBinRatio = 1.001;

// The value of rank `rank` (from 0) among the binned values.
size_t BinOfRank(const std::vector<uint64_t>& bins, uint64_t rank) {
  uint64_t seen = 0;
  for (size_t b = 0; b < bins.size(); ++b) {
    seen += bins[b];
    if (seen > rank) return b;
  }
  return bins.size() - 1;
}

std::string Duration(double seconds) {
  if (seconds >= 1.0) return StringPrintf("%.4g s", seconds);
  if (seconds >= 1e-3) return StringPrintf("%.4g ms", seconds * 1e3);
  return StringPrintf("%.4g us", seconds * 1e6);
}

}  // namespace

HostTimeBurstTally::HostTimeBurstTally() {
  const size_t bins =
      static_cast<size_t>(std::ceil(std::log(kHighestStepS / kLowestStepS) / std::log(kBinRatio)));
  step_bins_.assign(bins, 0);
  block_bins_.assign(bins, 0);
}

size_t HostTimeBurstTally::Bin(double step_s) const {
  if (!(step_s > kLowestStepS)) return 0;
  const double bin = std::floor(std::log(step_s / kLowestStepS) / std::log(kBinRatio));
  return std::min(step_bins_.size() - 1, static_cast<size_t>(bin));
}

double HostTimeBurstTally::BinValue(size_t bin) const {
  return kLowestStepS * std::pow(kBinRatio, static_cast<double>(bin) + 0.5);
}

void HostTimeBurstTally::Add(double t_s) {
  if (samples_ == 0) {
    first_t_s_ = t_s;
    block_start_s_ = t_s;
  } else {
    ++step_bins_[Bin(t_s - previous_t_s_)];
    if (++block_steps_ == kBlockSteps) {
      ++block_bins_[Bin((t_s - block_start_s_) / kBlockSteps)];
      block_start_s_ = t_s;
      block_steps_ = 0;
    }
  }
  previous_t_s_ = t_s;
  ++samples_;
}

HostTimeBursts HostTimeBurstTally::Result() const {
  HostTimeBursts result;
  if (samples_ < 2) return result;
  result.steps = samples_ - 1;
  result.mean_step_s = (previous_t_s_ - first_t_s_) / result.steps;
  result.median_step_s = BinValue(BinOfRank(step_bins_, result.steps / 2));
  const uint64_t blocks = result.steps / kBlockSteps;
  result.period_s = blocks == 0 ? result.mean_step_s : BinValue(BinOfRank(block_bins_, blocks / 2));
  uint64_t short_steps = 0;
  uint64_t long_steps = 0;
  for (size_t b = 0; b < step_bins_.size(); ++b) {
    const double step_s = BinValue(b);
    if (step_s < kShortStepPeriods * result.period_s) short_steps += step_bins_[b];
    if (step_s > kLongStepPeriods * result.period_s) long_steps += step_bins_[b];
  }
  result.short_share = static_cast<double>(short_steps) / result.steps;
  result.long_share = static_cast<double>(long_steps) / result.steps;
  result.bursty = result.steps >= kMinSteps && result.short_share >= kMinShortShare &&
                  result.long_share >= kMinLongShare;
  return result;
}

HostTimeBursts MeasureHostTimeBursts(const std::vector<double>& timestamp_s) {
  HostTimeBurstTally tally;
  for (double t_s : timestamp_s) tally.Add(t_s);
  return tally.Result();
}

std::string DescribeHostTimeBursts(const HostTimeBursts& bursts) {
  return StringPrintf(
      "%.0f%% of the steps below a third of the sample period of %s and %.0f%% above 1.5 "
      "periods; a median step of %s, a mean of %s (%.6g Hz)",
      100.0 * bursts.short_share, Duration(bursts.period_s).c_str(), 100.0 * bursts.long_share,
      Duration(bursts.median_step_s).c_str(), Duration(bursts.mean_step_s).c_str(),
      bursts.mean_rate_hz());
}

}  // namespace accelcal
