#ifndef ACCELCAL_ESTIMATION_TRIAD_STATIC_INTERVALS_H_
#define ACCELCAL_ESTIMATION_TRIAD_STATIC_INTERVALS_H_

// Static intervals of a triad log: where the sensor was held still.
//
// imu_tk's rule (Tedaldi et al., ICRA 2014; imu_tk's staticIntervalsDetector), reproduced
// (the window variances by running sums, within a few ulps of imu_tk's two passes for a log
// in counts, so the intervals are imu_tk's):
//   - for every sample i whose centred window [i - h, i + h] of w = 2h + 1 samples lies in
//     the log, the sample variance per axis over the window (divided by w - 1), and its norm
//     v_i = sqrt(var_x^2 + var_y^2 + var_z^2) (count^2 for a log in counts);
//   - samples with v_i < threshold are static; an interval starts at the first static
//     sample after a moving one and ends at the last static one before the next moving one;
//     an interval still open at i = n - h - 1 ends there;
//   - the threshold is k times the variance norm of an initial rest (the samples from the
//     first to the one nearest t_0 + rest duration, variances divided by N - 1).
// The first h and last h samples are never classified.

#include <array>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "common/triad_sample_source.h"

namespace accelcal {

struct StaticInterval {
  int start = 0;  // first sample (0-based)
  int end = 0;    // last sample, inclusive
  double start_s = 0.0;
  double end_s = 0.0;
  double duration_s = 0.0;               // end_s - start_s
  std::array<double, 3> mean{};          // per axis, in the log's unit
  std::array<double, 3> noise_stddev{};  // per axis, sample standard deviation (N - 1)
  int sample_count() const { return end - start + 1; }
};

// Mean and sample variance (divided by N - 1) per axis of samples [start, end].
std::array<double, 3> IntervalMean(const TriadLog& log, int start, int end);
std::array<double, 3> IntervalVariance(const TriadLog& log, int start, int end);

// The last sample of imu_tk's initial rest of `duration_s`: the sample whose time is nearest
// t_0 + duration_s (the later one on a tie), or the last sample.
int InitialRestEnd(const TriadLog& log, double duration_s);

// v_i for every sample (0 where the window does not fit); `window` is odd and >= 3.
std::vector<double> SlidingVarianceNorm(const TriadLog& log, int window);

// The intervals where `variance_norm` (from SlidingVarianceNorm with `window`) is below
// `threshold`, with their statistics.
std::vector<StaticInterval> DetectStaticIntervals(const TriadLog& log,
                                                  const std::vector<double>& variance_norm,
                                                  int window, double threshold);

// Fills the statistics of an interval whose start and end are set.
void DescribeInterval(const TriadLog& log, StaticInterval* interval);

// The same from samples read back (two passes over the interval's range, the mean's and the
// deviations'), whatever the interval's length; the numbers are DescribeInterval's to the bit.
Status DescribeInterval(const TriadSampleSource& log, StaticInterval* interval);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_STATIC_INTERVALS_H_
