#ifndef ACCELCAL_COMMON_TILT_MOTION_H_
#define ACCELCAL_COMMON_TILT_MOTION_H_

// How the table moves during a tilt test, read from its reported angles alone: which way it
// turns at each sample, and which angles it holds. Discovery's checks of what remains
// (estimation/tilt_table/residual_checks.h) and the simulator's disturbances
// (simulation/disturbances.h) read the motion the same way.

#include <vector>

namespace accelcal {

// The direction the table turns at each sample: +1 while theta increases, -1 while it
// decreases. A sample where the table holds still keeps the direction of the last move, and
// the samples before the first move take that move's; a move is a change of at least
// kTurnTolerance from where the direction was last decided, so that jitter in a held angle
// does not flip it. All zero when the table never moves.
inline constexpr double kTurnTolerance = 1e-3;  // rad
std::vector<double> TurnDirection(const std::vector<double>& theta_rad);

// The static positions of a test: runs of at least kMinPositionSamples consecutive samples
// with the same reported theta, as [begin, end) sample ranges. Empty for a sweep.
inline constexpr int kMinPositionSamples = 5;
struct StaticPosition {
  int begin = 0;
  int end = 0;
};
std::vector<StaticPosition> StaticPositions(const std::vector<double>& theta_rad);

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_TILT_MOTION_H_
