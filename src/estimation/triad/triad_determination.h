#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_DETERMINATION_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_DETERMINATION_H_

// Which of a triad calibration's 9 parameters the poses determine too poorly to vouch for, and
// which poses would determine them (issue 30, item 5), by the rule and thresholds of
// estimation/statistics/parameter_determination.h (an angle's sigma beyond 1 mrad, a gain's
// beyond 1e-3 of the gain, an offset's beyond 0.1 of s_k, the per-sample noise the fit pooled
// on axis k, or a |correlation| beyond 0.99 with another parameter), which the gyroscope's
// list shares (estimation/gyroscope/gyroscope_determination.h).
//
// The poses that would determine it follow from what the fit can see. Each pose gives the norm
// |T K (u - b)| = g with an unknown direction, so to first order the data see
//   |a|^2 ~ sum_k v_k^2 - 2 (yz v_x v_y - zy v_x v_z + zx v_y v_z),  v_k = gain_k (u_k - b_k):
// an angle through the product of the two axes it couples (misalignment_yz: x and y;
// misalignment_zy: x and z; misalignment_zx: y and z), largest with gravity midway between
// them (45 degrees in their plane, |n_j n_k| = 0.5); a gain through v_k^2, largest with axis k
// along +-g; an offset through the sign of v_k, so with axis k along +g AND along -g. The
// suggestion says what the session's poses reached of each, from their fitted directions.

#include <string>
#include <vector>

#include "estimation/statistics/parameter_determination.h"
#include "estimation/triad/triad_ml_calibration.h"

namespace accelcal {

using TriadDeterminationOptions = DeterminationThresholds;
using TriadCorrelatedParameter = CorrelatedParameter;
using TriadPoorlyDetermined = PoorlyDeterminedParameter;  // index: models/triad.h's block order

// From a fit's parameters, covariance, per-sample noise and fitted gravity directions; in
// block order, empty when every parameter is well determined. `unit`: the log's, for the
// offsets' threshold in words.
std::vector<TriadPoorlyDetermined> PoorlyDeterminedTriadParameters(
    const TriadMlResult& ml, const std::string& unit,
    const TriadDeterminationOptions& options = TriadDeterminationOptions());

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_DETERMINATION_H_
