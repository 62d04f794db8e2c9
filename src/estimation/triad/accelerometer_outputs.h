#ifndef ACCELCAL_ESTIMATION_TRIAD_ACCELEROMETER_OUTPUTS_H_
#define ACCELCAL_ESTIMATION_TRIAD_ACCELEROMETER_OUTPUTS_H_

// Two things a log given as an accelerometer's can be instead, told from its outputs before any
// pose is looked for, so that the refusal names the cause rather than what failed downstream of
// it (a fit that cannot determine the triad, or an offset that looks like another unit):
//
//   - clipped samples: an axis saturated at full scale sits at its largest (or smallest) value
//     for whole stretches of samples, while elsewhere its noise moves it by at least a step from
//     one sample to the next. A pose held there has a mean that is the range's end, not the
//     specific force. (An output whose noise is below its step sits on one level in every pose
//     anyway; its clipping cannot be told from the log, and is not claimed.)
//   - a gyroscope's outputs: at rest a gyroscope reads its offset whatever the pose, so after
//     each turn the means of the log's quiet windows return where they were, hardly spread
//     beyond their noise, where an accelerometer's move by up to 2 g from pose to pose.
//
// Each refusal is one line naming the axis, the values and the samples, and what to do; no file
// name (the caller adds it).

#include "common/status.h"
#include "common/triad_log.h"

namespace accelcal {

// No axis sits at its maximum or minimum for a stretch of kMinClippedRun samples or more while
// its output otherwise changes from most samples to the next.
constexpr int kMinClippedRun = 25;
Status CheckNotClipped(const TriadLog& log);

// The means of the quietest half of the log's windows (of about one second) spread, on some
// axis, by more than kMinOrientationSpread times their noise, in a log turned at least kMinTurns
// times (runs of windows far louder than the quiet ones) between its rests.
constexpr double kMinOrientationSpread = 20.0;
constexpr int kMinTurns = 5;
Status CheckOutputsFollowOrientation(const TriadLog& log);

// Both, clipping first.
Status CheckAccelerometerOutputs(const TriadLog& log);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_ACCELEROMETER_OUTPUTS_H_
