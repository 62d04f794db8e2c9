#include "estimation/triad/static_intervals.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "estimation/triad/noise_floor_detector.h"

namespace accelcal {

namespace {

std::array<double, 3> SourceMean(const TriadSampleSource& log, int start, int end, Status* status) {
  std::array<double, 3> sum{};
  *status = ForEachSample(log, start, end, [&](size_t, double, const std::array<double, 3>& u) {
    for (int k = 0; k < 3; ++k) sum[k] += u[k];
  });
  const double count = end - start + 1;
  for (int k = 0; k < 3; ++k) sum[k] /= count;
  return sum;
}

// Two passes (the mean, then the squared deviations from it), as imu_tk computes it, so that
// a sample's variance norm and hence its side of the threshold are the same to the last bit
// as far as the order of the sums allows.
std::array<double, 3> VarianceAbout(const TriadSampleSource& log, int start, int end,
                                    const std::array<double, 3>& mean, Status* status) {
  std::array<double, 3> variance{};
  *status = ForEachSample(log, start, end, [&](size_t, double, const std::array<double, 3>& u) {
    for (int k = 0; k < 3; ++k) {
      const double deviation = u[k] - mean[k];
      variance[k] += deviation * deviation;
    }
  });
  const double dof = end - start;
  for (int k = 0; k < 3; ++k) variance[k] /= dof;
  return variance;
}

}  // namespace

std::array<double, 3> IntervalMean(const TriadLog& log, int start, int end) {
  Status status;  // a log in memory reads without fail
  return SourceMean(TriadLogSamples(log), start, end, &status);
}

std::array<double, 3> IntervalVariance(const TriadLog& log, int start, int end) {
  const TriadLogSamples samples(log);
  Status status;
  return VarianceAbout(samples, start, end, SourceMean(samples, start, end, &status), &status);
}

int InitialRestEnd(const TriadLog& log, double duration_s) {
  const int last = static_cast<int>(log.size()) - 1;
  const double end_s = log.timestamp_s.front() + duration_s;
  if (end_s >= log.timestamp_s[last]) return last;
  // Bisection to the two samples around end_s, then the nearer one.
  int low = 0;
  int high = last;
  while (high - low > 1) {
    const int middle = (low + high) / 2;
    if (end_s > log.timestamp_s[middle]) {
      low = middle;
    } else {
      high = middle;
    }
  }
  return end_s - log.timestamp_s[low] < log.timestamp_s[high] - end_s ? low : high;
}

static double Norm(const std::array<double, 3>& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

namespace {

// The largest |u - u_0| over the log when every output is a whole number (imu_tk's logs are
// ADC counts) below 2^52 in magnitude; -1 otherwise.
double IntegerCountsSpread(const TriadLog& log) {
  double spread = 0.0;
  for (const std::array<double, 3>& u : log.output) {
    for (int k = 0; k < 3; ++k) {
      // The range first: the conversion below is defined only inside int64's.
      if (!(std::abs(u[k]) < 0x1p52)) return -1.0;
      if (static_cast<double>(static_cast<int64_t>(u[k])) != u[k]) return -1.0;
      spread = std::max(spread, std::abs(u[k] - log.output.front()[k]));
    }
  }
  return spread;
}

// The window variance of integer counts from exact running sums: with S and Q the sums of the
// deviations from the first sample and of their squares, w Q - S^2 is an exact integer, and
// the variance (w Q - S^2) / (w (w - 1)) is rounded once or twice, against the two-pass
// variance's rounding at every term; the two agree to a few ulps. `Wide` holds w Q and S^2.
template <typename Wide>
std::vector<std::array<double, 3>> IntegerWindowVariances(const TriadLog& log, int window) {
  const int n = static_cast<int>(log.size());
  std::vector<std::array<double, 3>> variances(n - window + 1);
  const double denominator = static_cast<double>(window) * (window - 1);
  for (int axis = 0; axis < 3; ++axis) {
    const double reference = log.output.front()[axis];
    auto deviation = [&](int i) { return static_cast<int64_t>(log.output[i][axis] - reference); };
    int64_t sum = 0;
    int64_t sum_squares = 0;
    for (int i = 0; i < window; ++i) {
      sum += deviation(i);
      sum_squares += deviation(i) * deviation(i);
    }
    for (int j = 0;; ++j) {
      const Wide scaled = static_cast<Wide>(window) * sum_squares - static_cast<Wide>(sum) * sum;
      variances[j][axis] = static_cast<double>(scaled) / denominator;
      if (j + window >= n) break;
      const int64_t leaving = deviation(j);
      const int64_t entering = deviation(j + window);
      sum += entering - leaving;
      sum_squares += entering * entering - leaving * leaving;
    }
  }
  return variances;
}

}  // namespace

// Running sums rather than imu_tk's two passes per window: O(n) instead of O(n w). Exact
// integer sums for a log of counts; otherwise the noise-floor detector's re-anchored sums
// (WindowVariances), which differ from the two-pass variance in the last bits of a rest that
// follows a large move. imu_tk's Xsens log gives the same intervals at every k as the two
// passes (tests/imu_tk_calibration_test.cc).
std::vector<double> SlidingVarianceNorm(const TriadLog& log, int window) {
  const int n = static_cast<int>(log.size());
  const int half = window / 2;
  std::vector<double> norm(n, 0.0);
  if (n < window) return norm;
  // A spread below 2^24 keeps S and Q in int64 for any window below 2^31 samples, and
  // w Q - S^2 too while w^2 spread^2 < 2^62; beyond, 128 bits.
  const double spread = IntegerCountsSpread(log);
  const double scaled_bound = static_cast<double>(window) * window * spread * spread;
  std::vector<std::array<double, 3>> variances;
  if (spread < 0.0 || spread > 0x1p24) {
    variances = WindowVariances(log, window);
  } else if (scaled_bound < 0x1p62) {
    variances = IntegerWindowVariances<int64_t>(log, window);
  } else {
    variances = IntegerWindowVariances<__int128>(log, window);
  }
  for (size_t j = 0; j < variances.size(); ++j) norm[j + half] = Norm(variances[j]);
  return norm;
}

void DescribeInterval(const TriadLog& log, StaticInterval* interval) {
  (void)DescribeInterval(TriadLogSamples(log), interval);  // a log in memory reads without fail
}

Status DescribeInterval(const TriadSampleSource& log, StaticInterval* interval) {
  TriadLog ends;
  ACCELCAL_RETURN_IF_ERROR(log.Read(interval->start, 1, &ends));
  interval->start_s = ends.timestamp_s[0];
  ACCELCAL_RETURN_IF_ERROR(log.Read(interval->end, 1, &ends));
  interval->end_s = ends.timestamp_s[0];
  interval->duration_s = interval->end_s - interval->start_s;
  Status status;
  interval->mean = SourceMean(log, interval->start, interval->end, &status);
  ACCELCAL_RETURN_IF_ERROR(status);
  if (interval->end > interval->start) {
    const std::array<double, 3> variance =
        VarianceAbout(log, interval->start, interval->end, interval->mean, &status);
    ACCELCAL_RETURN_IF_ERROR(status);
    for (int k = 0; k < 3; ++k) interval->noise_stddev[k] = std::sqrt(variance[k]);
  }
  return Status::Ok();
}

std::vector<StaticInterval> DetectStaticIntervals(const TriadLog& log,
                                                  const std::vector<double>& variance_norm,
                                                  int window, double threshold) {
  const int n = static_cast<int>(log.size());
  const int half = window / 2;
  std::vector<StaticInterval> intervals;
  bool inside = false;
  StaticInterval current;
  for (int i = half; i < n - half; ++i) {
    const bool still = variance_norm[i] < threshold;
    if (!inside && still) {
      current.start = i;
      inside = true;
    } else if (inside && !still) {
      current.end = i - 1;
      intervals.push_back(current);
      inside = false;
    }
  }
  if (inside) {
    current.end = n - half - 1;
    intervals.push_back(current);
  }
  for (StaticInterval& interval : intervals) DescribeInterval(log, &interval);
  return intervals;
}

}  // namespace accelcal
