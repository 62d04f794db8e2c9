#ifndef ACCELCAL_ESTIMATION_TRIAD_NOISE_FLOOR_STREAM_H_
#define ACCELCAL_ESTIMATION_TRIAD_NOISE_FLOOR_STREAM_H_

// The noise-floor detector (estimation/triad/noise_floor_detector.h) in passes over a log that is
// not held (issue 36, item 2): the same intervals, floors and thresholds, to the last bit, from
// memory that does not grow with the log's length. What it holds: the window's w + 1 samples,
// the exact rank selections' buffers (common/streaming_rank.h; the 5 % quantiles of the window
// variances, the still windows' medians and 10 % quantiles), one candidate run's window
// variances at a time (a pose's, for its own floor), and the intervals found.
//
// Passes, each reading the samples in order and recomputing V: the 5 % quantiles (one to four
// passes, OutputSteps in the first); the per-pose rule's runs, their floors, the stuck-axis counts
// and the ratios' quantiles (one to four); the single floor's provisional still windows' medians
// (one to four), its still windows' medians and 10 % quantiles (one to four); then two short
// reads per interval for its mean and noise.
//
// A candidate run longer than max_run_windows (a still log of hours is one run) is not held:
// its floor's medians are selected in passes over its own windows (issue 49, item 1), the same
// values, so that memory stays bounded whatever the run's length.
//
// It decides only what the whole-log detector accepts: when that detector would refuse, or
// would take the per-pose rule because the single floor refuses (whose message it then
// quotes), *decided is false and nothing is known; the caller reads the log whole to say why (a
// refused log's cost, as apply's). options.min_intervals must be 0 (the smaller windows' retry of a
// refusal is not streamed).

#include <cstddef>

#include "common/status.h"
#include "common/triad_sample_source.h"
#include "estimation/triad/noise_floor_detector.h"

namespace accelcal {

struct NoiseFloorStreamOptions {
  NoiseFloorOptions detector;
  // The longest candidate run (windows) whose variances are held for its floor: 2^20, 24 MB;
  // a longer one's floor is found in passes over it.
  size_t max_run_windows = size_t{1} << 20;
};

Status DetectStaticIntervalsFromNoiseFloorStreamed(const TriadSampleSource& log,
                                                   const NoiseFloorStreamOptions& options,
                                                   NoiseFloorDetection* detection, bool* decided);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_NOISE_FLOOR_STREAM_H_
