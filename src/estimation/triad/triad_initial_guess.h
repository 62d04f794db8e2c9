#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_INITIAL_GUESS_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_INITIAL_GUESS_H_

// Where the maximum-likelihood triad fit starts when no other calibration is at hand: per
// axis, the poses' means span about [b - g/K, b + g/K] when the poses point both ways along
// it, so
//   offset_k = (max_p ubar_p,k + min_p ubar_p,k) / 2,   gain_k = 2 g / (max - min),
// and the angles 0. Good to a few percent for poses spread over the sphere, which is all
// Levenberg-Marquardt needs. An axis whose means span less than half the widest axis's (the
// poses barely turn it) takes the widest axis's gain; such poses cannot determine the triad,
// and the fit's identifiability check then says which poses to add.

#include <vector>

#include "common/triad_log.h"
#include "models/triad.h"

namespace accelcal {

// `poses` must not be empty; an axis whose means do not vary gets gain 1 per unit.
TriadParameters TriadStartFromPoses(const std::vector<TriadPoseMean>& poses, double gravity_mps2);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_INITIAL_GUESS_H_
