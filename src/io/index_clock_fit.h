#ifndef ACCELCAL_IO_INDEX_CLOCK_FIT_H_
#define ACCELCAL_IO_INDEX_CLOCK_FIT_H_

// The samples' times from their sample-number column when the host's receive times cannot be
// used as such (io/host_time_bursts.h). The device samples on its own clock, sample n at
// t0 + n / R; the host receives it after a delay that is never negative (buffering, the link's
// connection interval, scheduling):
//
//   host_time_s[j] = t0 + index[j] / R + delay[j],   delay[j] >= 0.
//
// So the device's clock, read on the host's, is the lower envelope of the points
// (index, host time), not a least-squares line through them (which the delays would lift and,
// when their pattern changes along the log, tilt). The line kept is the one below every point
// that is highest on average: an edge of the points' lower convex hull, the one spanning the
// mean index (Moon, Skelly and Towsley, "Estimation and removal of clock skew from network
// delay measurements", INFOCOM 1999). R is then the sample rate in the host's seconds, and its
// distance from a usual nominal rate (100 Hz, 104 Hz, 204.8 Hz, ...) the device clock's drift
// against the host's.
//
// The rate's tolerance: the envelope touches the points only where some sample had the least
// delay; in each of kToleranceBlocks blocks along the index the least delay above the line is
// how far the line could move there, and tilting it by the largest such gap over half the
// index span bounds the slope's error.
//
// The index jumps by more than 1 where samples were lost (the device counted them, the host
// never received them): they keep their index's time, and their number is reported.

#include <string>
#include <vector>

#include "common/status.h"

namespace accelcal {

struct IndexClockFit {
  double rate_hz = 0.0;            // samples per second of the host's clock
  double rate_tolerance_hz = 0.0;  // see above
  double origin_s = 0.0;           // the line's time at index 0 (the host's time axis)
  // The usual rate within kMaxDriftFromNominal of rate_hz, else 0; the drift then in ppm.
  double nominal_rate_hz = 0.0;
  double clock_drift_ppm = 0.0;
  long long dropped_samples = 0;  // the index's jumps beyond 1, summed
  double largest_delay_s = 0.0;   // the largest host delay above the line
};

// Fits the device clock to `index` (whole numbers, strictly increasing: a counter) and
// `host_time_s` (increasing), one each per sample. Fails, naming the sample, when the index is
// not a counter: not a whole number, not increasing, or skipping more samples than the log
// holds. `timestamp_s`: the device clock's time of each sample, origin_s + index / rate_hz.
Status FitIndexClock(const std::vector<double>& index, const std::vector<double>& host_time_s,
                     IndexClockFit* fit, std::vector<double>* timestamp_s);

// The fit in words, for the log's read: line: "at a fitted 99.87 +- 0.002 Hz (the device clock
// -1300 ppm from a nominal 100 Hz, as the host counts time), 3 dropped samples".
std::string DescribeIndexClockFit(const IndexClockFit& fit);

}  // namespace accelcal

#endif  // ACCELCAL_IO_INDEX_CLOCK_FIT_H_
