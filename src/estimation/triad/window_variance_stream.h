#ifndef ACCELCAL_ESTIMATION_TRIAD_WINDOW_VARIANCE_STREAM_H_
#define ACCELCAL_ESTIMATION_TRIAD_WINDOW_VARIANCE_STREAM_H_

// The noise-floor detector's window variances V_j,k (estimation/triad/noise_floor_detector.h)
// one window at a time from samples handed over in order, holding w + 1 samples: sliding sums
// re-anchored at the window's first sample every w windows, so that rounding neither
// accumulates nor cancels and an output constant over a window gives exactly 0. The one
// implementation of them: WindowVariances collects this stream's values over a whole log.

#include <algorithm>
#include <array>
#include <vector>

namespace accelcal {

class WindowVarianceStream {
 public:
  explicit WindowVarianceStream(int window)
      : window_(window), ring_(static_cast<size_t>(window) + 1) {}

  // The next sample's outputs; true when it completes the window j = i - w + 1 (i counted from
  // 0), whose variances are then variance().
  bool Add(const std::array<double, 3>& output) {
    const long long i = samples_++;
    const size_t size = ring_.size();
    ring_[static_cast<size_t>(i) % size] = output;
    const long long j = i - window_ + 1;
    if (j < 0) return false;
    for (int axis = 0; axis < 3; ++axis) {
      if (j % window_ == 0) {
        // Deviations from a sample of the window keep sum_squares - sum^2 / w free of the
        // cancellation a large offset (32768 counts) would cause.
        reference_[axis] = ring_[static_cast<size_t>(j) % size][axis];
        sum_[axis] = 0.0;
        sum_squares_[axis] = 0.0;
        for (long long s = j; s < j + window_; ++s) {
          const double deviation = ring_[static_cast<size_t>(s) % size][axis] - reference_[axis];
          sum_[axis] += deviation;
          sum_squares_[axis] += deviation * deviation;
        }
      } else {
        const double leaving = ring_[static_cast<size_t>(j - 1) % size][axis] - reference_[axis];
        const double entering = output[axis] - reference_[axis];
        sum_[axis] += entering - leaving;
        sum_squares_[axis] += entering * entering - leaving * leaving;
      }
      variance_[axis] =
          std::max(0.0, (sum_squares_[axis] - sum_[axis] * sum_[axis] / window_) / (window_ - 1));
    }
    return true;
  }

  const std::array<double, 3>& variance() const { return variance_; }

 private:
  const int window_;
  std::vector<std::array<double, 3>> ring_;
  long long samples_ = 0;
  std::array<double, 3> reference_{};
  std::array<double, 3> sum_{};
  std::array<double, 3> sum_squares_{};
  std::array<double, 3> variance_{};
};

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_WINDOW_VARIANCE_STREAM_H_
