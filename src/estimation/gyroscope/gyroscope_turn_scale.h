#ifndef ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_TURN_SCALE_H_
#define ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_TURN_SCALE_H_

// Whether the gyroscope's outputs are in the unit (and at the gain) the fit starts from, seen in
// the turns before any fit: a turn carries its pose's gravity direction n_p to the next pose's
// n_p+1 (the accelerometer's), so the rates w = T K (u - b) at the start's gains, scaled by s,
// integrate over the turns to rotations that do so best at s = 1 when the unit and gain are
// right. Outputs in counts taken for deg/s (a factor 16.4 at +-2000 deg/s), deg/s for rad/s (57)
// or a start gain off by such a factor leave the maximum-likelihood fit nothing it can repair:
// its turns' sampling error then absorbs the misses and the gains stay near their start, a
// calibration in the wrong unit with a verdict (measured on mimu4444 run 1 IMU 1 with
// --gyro_unit=deg/s: gains 0.0168 (rad/s)/(deg/s) where the truth is 0.00106, "missing", exit 0).
//
// The scale: the s on a grid of 2^(k/2) over [1/1024, 1024] that minimises the mean over the
// turns of |R(s)^T n_p - n_p+1|^2, refined by a golden-section search between its neighbours; on
// the 8 turns that tilt most (about 1% of calibrate_imu --mode=ml's time on imu_tk's Xsens pair)
// among those that never sit at an axis's extreme output for 3 samples in a row (a clipped turn's
// integral is short). Units differ by larger factors than 3 (counts of 1/16.4 to 1/131 deg/s,
// deg/s against rad/s 57), and a start gain within 3 of the truth the fit repairs itself.

#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/triad/static_intervals.h"
#include "models/gyroscope.h"
#include "models/gyroscope_units.h"

namespace accelcal {

struct GyroscopeTurnScale {
  int turns = 0;          // the turns used (at most 8)
  double scale = 1.0;     // the best s
  double rms_at_one = 0;  // sqrt(mean over turns of |R^T n_p - n_p+1|^2) at s = 1 (rad, about)
  double rms_at_scale = 0;
};

// `directions`: the accelerometer's n_p, one per interval (time order); the gyroscope's offsets
// start at the mean of the poses' means, as the fit's do.
GyroscopeTurnScale MeasureGyroscopeTurnScale(const TriadLog& log,
                                             const std::vector<StaticInterval>& intervals,
                                             const std::vector<std::array<double, 3>>& directions,
                                             const GyroscopeParameters& start);

// A refusal when the turns say the rates are off by a factor of 3 or more (and fit 4 times
// better there, at a miss of 3 degrees or more at s = 1), naming the factor and the flags that
// would be right: the physical unit the scaled gain matches within 10%, else counts with
// --initial_gyro_gain at the scaled gain. Ok otherwise (and when fewer than 3 turns).
Status CheckGyroscopeTurnScale(const GyroscopeTurnScale& measured, const GyroscopeParameters& start,
                               GyroscopeOutputUnit unit);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_TURN_SCALE_H_
