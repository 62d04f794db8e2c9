#ifndef ACCELCAL_ESTIMATION_STATISTICS_PARAMETER_DETERMINATION_H_
#define ACCELCAL_ESTIMATION_STATISTICS_PARAMETER_DETERMINATION_H_

// The rule by which a calibration names the parameters its data determine too poorly to vouch
// for (issue 30, item 5, for the accelerometer: estimation/triad/triad_determination.h; issue 44,
// item 6, for the gyroscope: estimation/gyroscope/gyroscope_determination.h). Nothing is refused
// by it: a parameter the data cannot determine at all is the fit's refusal; this names the ones
// they determine, but loosely. A parameter is poorly determined when
//
//   - its sigma exceeds a stated fraction of a typical value: an angle 1 mrad; a gain 1e-3 of
//     the gain itself; an offset 0.1 of one sample's noise standard deviation on its axis, or
//   - its correlation with another parameter exceeds 0.99 in magnitude: the data determine a
//     combination of the two, not each (the sigma alone can hide this when both are small).
//
// What would determine it (poses for the accelerometer, turns for the gyroscope) is the
// geometry's to say.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace accelcal {

// The thresholds, the same for the accelerometer and the gyroscope.
struct DeterminationThresholds {
  double angle_sigma_rad = 1e-3;       // misalignment angles
  double gain_relative_sigma = 1e-3;   // sigma / |gain|
  double offset_noise_fraction = 0.1;  // sigma / s_k, s_k one sample's noise on axis k
  double correlation = 0.99;           // |rho| beyond which two parameters are confounded
};

struct CorrelatedParameter {
  std::string parameter;
  double correlation = 0.0;
};

struct PoorlyDeterminedParameter {
  int index = 0;           // the geometry's parameter order
  std::string parameter;   // its name
  std::string reason;      // in words: the sigma against its threshold, and/or the correlations
  double sigma = 0.0;      // the parameter's unit
  double threshold = 0.0;  // the sigma threshold, the parameter's unit
  bool sigma_over_threshold = false;
  std::vector<CorrelatedParameter> correlated_with;  // |rho| > the correlation threshold
  std::string suggestion;  // what would determine it (the geometry's words)
};

// Parameter `p` of `names` (covariance's order; the first names.size() rows of `covariance` are
// judged) against its sigma threshold (`threshold`, in the parameter's unit; `threshold_words`
// states it in the reason) and its correlations beyond `correlation` with the others. Returns true
// and fills `entry` (all but the suggestion) when it is poorly determined. A sigma that is not a
// number is over any threshold.
bool JudgeParameterDetermination(int p, const std::vector<std::string>& names,
                                 const Eigen::MatrixXd& covariance, double threshold,
                                 const std::string& threshold_words, double correlation,
                                 PoorlyDeterminedParameter* entry);

// The names of `list`, joined by ", " ("misalignment_yz, gain_y").
std::string PoorlyDeterminedNames(const std::vector<PoorlyDeterminedParameter>& list);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_STATISTICS_PARAMETER_DETERMINATION_H_
