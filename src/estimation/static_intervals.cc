#include "estimation/static_intervals.h"

#include <cmath>

namespace accelcal {

std::array<double, 3> IntervalMean(const TriadLog& log, int start, int end) {
  std::array<double, 3> sum{};
  for (int i = start; i <= end; ++i) {
    for (int k = 0; k < 3; ++k) sum[k] += log.output[i][k];
  }
  const double count = end - start + 1;
  for (int k = 0; k < 3; ++k) sum[k] /= count;
  return sum;
}

// Two passes (the mean, then the squared deviations from it), as imu_tk computes it, so that
// a sample's variance norm and hence its side of the threshold are the same to the last bit
// as far as the order of the sums allows.
std::array<double, 3> IntervalVariance(const TriadLog& log, int start, int end) {
  const std::array<double, 3> mean = IntervalMean(log, start, end);
  std::array<double, 3> variance{};
  for (int i = start; i <= end; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double deviation = log.output[i][k] - mean[k];
      variance[k] += deviation * deviation;
    }
  }
  const double dof = end - start;
  for (int k = 0; k < 3; ++k) variance[k] /= dof;
  return variance;
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

std::vector<double> SlidingVarianceNorm(const TriadLog& log, int window) {
  const int n = static_cast<int>(log.size());
  const int half = window / 2;
  std::vector<double> norm(n, 0.0);
  for (int i = half; i < n - half; ++i) norm[i] = Norm(IntervalVariance(log, i - half, i + half));
  return norm;
}

void DescribeInterval(const TriadLog& log, StaticInterval* interval) {
  interval->start_s = log.timestamp_s[interval->start];
  interval->end_s = log.timestamp_s[interval->end];
  interval->duration_s = interval->end_s - interval->start_s;
  interval->mean = IntervalMean(log, interval->start, interval->end);
  if (interval->end > interval->start) {
    const std::array<double, 3> variance = IntervalVariance(log, interval->start, interval->end);
    for (int k = 0; k < 3; ++k) interval->noise_stddev[k] = std::sqrt(variance[k]);
  }
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
