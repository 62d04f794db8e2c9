#ifndef ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_DETERMINATION_H_
#define ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_DETERMINATION_H_

// Which of the gyroscope's 12 calibration unknowns (the 9 of models/gyroscope.h's block, then the
// 3 offsets) a session determines too poorly to vouch for, and what would determine them (issue
// 44, item 6): the accelerometer's rule and thresholds (estimation/statistics/
// parameter_determination.h: an angle's sigma beyond 1 mrad, a gain's beyond 1e-3 of the gain,
// an offset's beyond 0.1 of its axis's per-sample noise, or a |correlation| beyond 0.99 with
// another unknown), on GyroscopeMlResult::covariance.
//
// What determines them: the turn residual compares the rotation T K (u - b) integrates to with
// the one the accelerometer's poses see, and column j of T K multiplies the reading of axis j,
// so a gain or a misalignment column is determined by turns about its body axis
// (GyroscopeTurnAxisOf: gain_k by turns about k; misalignment_yz and _yx by turns about y,
// _zy and _zx about z, _xz and _xy about x). The suggestion says how much of the session's
// turning went about that axis (GyroscopeMlResult::turned_about_rad: |w_k| integrated over the
// turns). The offsets come from every static pose's mean (and the turns), so more or longer
// poses determine them.
//
// The effect coefficients estimated beyond the 12 are not judged (as the accelerometer's list
// judges its 9 parameters only); their sigma is in the table beside them.

#include <array>
#include <string>
#include <vector>

#include "estimation/gyroscope/gyroscope_ml_calibration.h"
#include "estimation/statistics/parameter_determination.h"

namespace accelcal {

// From a fit's unknowns, covariance, per-sample noise and turns; in the unknowns' order, empty
// when every one is well determined. `unit`: the log's (GyroscopeOutputUnitName), for the
// offsets' threshold in words.
std::vector<PoorlyDeterminedParameter> PoorlyDeterminedGyroscopeParameters(
    const GyroscopeMlResult& fit, const std::string& unit,
    const DeterminationThresholds& thresholds = DeterminationThresholds());

// What the gyroscope's verdict adds for `list`: "" when empty, else "; the session does not
// determine gyroscope_misalignment_yz, ... to the thresholds (poorly determined; turns about y
// and z would determine them)".
std::string PoorlyDeterminedClause(const std::vector<PoorlyDeterminedParameter>& list);

// The share of the turns' rotation about each body axis (turned_about_rad over its sum; 0 when
// the turns did not turn).
std::array<double, 3> GyroscopeTurnShares(const GyroscopeMlResult& fit);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_GYROSCOPE_GYROSCOPE_DETERMINATION_H_
