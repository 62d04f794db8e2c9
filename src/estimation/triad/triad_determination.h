#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_DETERMINATION_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_DETERMINATION_H_

// Which of a triad calibration's 9 parameters the poses determine too poorly to vouch for, and
// which poses would determine them (issue 30, item 5). Nothing is refused: a parameter the
// poses cannot determine at all is CalibrateTriadMl's refusal; this names the ones they
// determine, but loosely. A parameter is poorly determined when
//
//   - its sigma exceeds a stated fraction of a typical value: an angle 1 mrad; a gain 1e-3 of
//     the gain itself; an offset 0.1 of one sample's noise standard deviation on its axis
//     (s_k, the per-sample noise the fit pooled), or
//   - its correlation with another parameter exceeds 0.99 in magnitude: the poses determine a
//     combination of the two, not each (the sigma alone can hide this when both are small).
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

#include "estimation/triad/triad_ml_calibration.h"

namespace accelcal {

struct TriadDeterminationOptions {
  double angle_sigma_rad = 1e-3;       // misalignment angles
  double gain_relative_sigma = 1e-3;   // sigma / |gain|
  double offset_noise_fraction = 0.1;  // sigma / s_k, s_k one sample's noise on axis k
  double correlation = 0.99;           // |rho| beyond which two parameters are confounded
};

struct TriadCorrelatedParameter {
  std::string parameter;
  double correlation = 0.0;
};

struct TriadPoorlyDetermined {
  int index = 0;           // models/triad.h's block order
  std::string parameter;   // its name
  std::string reason;      // in words: the sigma against its threshold, and/or the correlations
  double sigma = 0.0;      // the parameter's unit
  double threshold = 0.0;  // the sigma threshold, the parameter's unit
  bool sigma_over_threshold = false;
  std::vector<TriadCorrelatedParameter> correlated_with;  // |rho| > options.correlation
  std::string suggestion;  // the pose orientations that would determine it
};

// From a fit's parameters, covariance, per-sample noise and fitted gravity directions; in
// block order, empty when every parameter is well determined. `unit`: the log's, for the
// offsets' threshold in words.
std::vector<TriadPoorlyDetermined> PoorlyDeterminedTriadParameters(
    const TriadMlResult& ml, const std::string& unit,
    const TriadDeterminationOptions& options = TriadDeterminationOptions());

// The names of `list`, joined by ", " ("misalignment_yz, gain_y").
std::string PoorlyDeterminedNames(const std::vector<TriadPoorlyDetermined>& list);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_DETERMINATION_H_
