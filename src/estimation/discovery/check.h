#ifndef ACCELCAL_ESTIMATION_DISCOVERY_CHECK_H_
#define ACCELCAL_ESTIMATION_DISCOVERY_CHECK_H_

// A check of what a fitted model leaves, one type for every sensor geometry: a statistic of
// the whitened residuals, its p-value under "the model and its noise model are right", a
// sentence, and (for a shape) the columns that describe it. The tilt table's checks are in
// estimation/tilt_table/residual_checks.h, the triad's in estimation/triad/triad_discovery.cc; each
// discovery procedure flags its family by Holm at its share of alpha (FlagByHolm).

#include <string>
#include <vector>

namespace accelcal {

// What a check's shape is a function of (issue 33, item 1), so that "unexplained" says what
// remains by the shape it has and what a user can do about it: the sensor's orientation (which
// axis, which power), time over the session (a trend, up then down, a step at one time), the
// direction the table turns (up-sweeps against down-sweeps), the order of the poses (one pose,
// offsets that jump between poses), full scale (outputs near one end of an axis's range that
// fall short), the motion of a gyroscope's turns (their rate, angle, duration, or how abruptly
// the rate changes between samples), or none of these (the noise: a scatter or a correlation
// with no shape).
enum class ShapeClass {
  kNoise,
  kOrientation,
  kTime,
  kTurnDirection,
  kPoseOrder,
  kFullScale,
  kTurnMotion
};
// "noise", "orientation", "time", "turn_direction", "pose_order", "full_scale", "turn_motion"
const char* ShapeClassName(ShapeClass shape_class);

struct ResidualCheck {
  std::string name;  // "x: 3 theta harmonic", "y: step", "endpoint", "chi2", ...
  int axis = -1;     // the axis the check looks at (0: x, 1: y, ...), -1: none or every one
  double statistic = 0.0;
  double dof = 0.0;  // of the statistic's reference distribution, 0 when it has none
  double p_value = 1.0;
  bool flagged = false;     // rejected by Holm in the checks' family
  std::string description;  // what it looks like, in numbers
  // The shape (one raw per-sample column per coefficient, m/s^2 per unit, on this axis);
  // empty for checks that describe no shape.
  std::vector<std::vector<double>> shape;
  ShapeClass shape_class = ShapeClass::kNoise;
  // What a user can do about it, in words ("log temperature and the orientation of x"); empty
  // when there is nothing more to say than the description.
  std::string advice;
};

// The check's sentence for the verdict: its description, then its advice.
std::string WhatRemains(const ResidualCheck& check);

// Holm's step-down at `alpha` over the checks' p-values: sets every check's `flagged`.
// Returns the number flagged.
int FlagByHolm(double alpha, std::vector<ResidualCheck>* checks);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_DISCOVERY_CHECK_H_
