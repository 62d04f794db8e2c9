#ifndef ACCELCAL_COMMON_STREAMING_RANK_H_
#define ACCELCAL_COMMON_STREAMING_RANK_H_

// The value of rank k (from 0, in increasing order; k = n / 2 is UpperMedian's, common/
// statistics.h) of a sequence of non-negative finite doubles too long to hold, found exactly in
// a few passes over the same sequence in bounded memory (about 24 MB whatever its length).
//
// A non-negative double's bit pattern, read as an unsigned integer, orders as the double does.
// Each pass narrows a range [low, high) of bit patterns known to hold the value: it counts the
// values below the range and builds a histogram of 2^20 bins over the range, and it keeps the
// values inside the range themselves while there are at most 2^21 of them. At the end of a pass
// the kept values give the answer at once (a log of up to two million samples: one pass); else
// the histogram's bin holding rank k is the next pass's range, 2^20 times narrower. The first
// range may be a hint (where the values are expected: an accelerometer's |a| near g), so that
// the second pass's bin is a few microns per second squared wide and its values fit; a value
// outside the hint costs one pass more. Whatever the data (a quantised log's millions of equal
// values included), at most four passes: a range one bit pattern wide is the value.

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

namespace accelcal {

class StreamingRankSelector {
 public:
  // The first pass's range [hint_low, hint_high) (non-negative doubles, hint_low < hint_high;
  // +inf for no upper bound). Smaller buffers (2^bin_bits bins, at most 2^kept_bits values kept)
  // for several selections at once cost more passes (at most 64 / bin_bits + 1).
  StreamingRankSelector(double hint_low, double hint_high, int bin_bits = 20, int kept_bits = 21)
      : bins_(size_t{1} << bin_bits),
        max_kept_(size_t{1} << kept_bits),
        low_(Bits(hint_low)),
        high_(Bits(hint_high)) {
    StartPass();
  }

  // Each value of the sequence, once per pass, in any order; the same values every pass (none
  // is needed once the value is known).
  void Add(double value) {
    if (done_) return;
    const uint64_t bits = Bits(value);
    if (bits < low_) {
      ++below_;
      return;
    }
    if (bits >= high_) return;
    ++histogram_[(bits - low_) >> shift_];
    if (kept_.size() < max_kept_) {
      kept_.push_back(bits);
    } else {
      overflow_ = true;
    }
  }

  // Ends a pass; true once the value of rank `rank` (from 0; the same at every pass; less than
  // the number of values) is known (then value()), else another pass is needed.
  bool FinishPass(uint64_t rank) {
    if (done_) return true;
    rank_ = rank;
    ++passes_;
    const uint64_t in_range = std::accumulate(histogram_.begin(), histogram_.end(), uint64_t{0});
    if (rank_ < below_) {  // below the range: the whole range below it next
      high_ = low_;
      low_ = 0;
    } else if (rank_ >= below_ + in_range) {  // above it
      low_ = high_;
      high_ = kEnd;
    } else if (!overflow_) {
      const auto nth = kept_.begin() + static_cast<long>(rank_ - below_);
      std::nth_element(kept_.begin(), nth, kept_.end());
      Finish(*nth);
    } else {
      uint64_t seen = below_;
      size_t bin = 0;
      while (seen + histogram_[bin] <= rank_) seen += histogram_[bin++];
      const uint64_t width = uint64_t{1} << shift_;
      low_ += bin * width;
      high_ = std::min(high_, low_ + width);
      if (high_ - low_ == 1) Finish(low_);
    }
    if (!done_) StartPass();
    return done_;
  }

  double value() const { return value_; }
  int passes() const { return passes_; }

 private:
  static constexpr uint64_t kEnd = uint64_t{0x7FF0000000000000};  // +inf's pattern

  static uint64_t Bits(double value) {
    uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof(bits));
    return bits;
  }

  void Finish(uint64_t bits) {
    std::memcpy(&value_, &bits, sizeof(bits));
    done_ = true;
    histogram_ = std::vector<uint64_t>();
    kept_ = std::vector<uint64_t>();
  }

  void StartPass() {
    shift_ = 0;
    while (((high_ - low_ - 1) >> shift_) >= bins_) ++shift_;
    histogram_.assign(((high_ - low_ - 1) >> shift_) + 1, 0);
    kept_.clear();
    overflow_ = false;
    below_ = 0;
  }

  size_t bins_;
  size_t max_kept_;
  uint64_t rank_ = 0;
  uint64_t low_, high_;
  int shift_ = 0;
  std::vector<uint64_t> histogram_;
  std::vector<uint64_t> kept_;
  bool overflow_ = false;
  uint64_t below_ = 0;
  int passes_ = 0;
  bool done_ = false;
  double value_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_STREAMING_RANK_H_
