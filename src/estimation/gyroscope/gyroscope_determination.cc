#include "estimation/gyroscope/gyroscope_determination.h"

#include <cmath>
#include <set>

#include "common/format.h"

namespace accelcal {
namespace {

// An axis that got half of an even share of the turning or more was turned about: what it lacks
// is more of the same, not another axis.
constexpr double kFairShare = 1.0 / 6.0;

}  // namespace

std::string PoorlyDeterminedClause(const std::vector<PoorlyDeterminedParameter>& list) {
  if (list.empty()) return "";
  std::set<std::string> axes;
  bool offsets = false;
  for (const PoorlyDeterminedParameter& entry : list) {
    const std::string axis = GyroscopeTurnAxisOf(entry.index, {});
    if (axis.empty()) {
      offsets = true;
    } else {
      axes.insert(axis);
    }
  }
  std::string what;
  if (!axes.empty()) {
    std::string joined;
    size_t i = 0;
    for (const std::string& axis : axes) {
      joined += (i == 0 ? "" : i + 1 == axes.size() ? " and " : ", ") + axis;
      ++i;
    }
    what = "turns about " + joined;
  }
  if (offsets) what += std::string(what.empty() ? "" : ", and ") + "more static poses";
  return "; the session does not determine " + PoorlyDeterminedNames(list) +
         " to the thresholds (poorly determined; " + what + " would determine " +
         (list.size() == 1 ? "it" : "them") + ")";
}

std::array<double, 3> GyroscopeTurnShares(const GyroscopeMlResult& fit) {
  const double total = fit.turned_about_rad[0] + fit.turned_about_rad[1] + fit.turned_about_rad[2];
  std::array<double, 3> shares{};
  if (!(total > 0.0)) return shares;
  for (int k = 0; k < 3; ++k) shares[k] = fit.turned_about_rad[k] / total;
  return shares;
}

std::vector<PoorlyDeterminedParameter> PoorlyDeterminedGyroscopeParameters(
    const GyroscopeMlResult& fit, const std::string& unit,
    const DeterminationThresholds& thresholds) {
  std::vector<PoorlyDeterminedParameter> list;
  if (fit.covariance.rows() < kGyroscopeCalibrationCount ||
      static_cast<int>(fit.names.size()) < kGyroscopeCalibrationCount)
    return list;
  const std::vector<std::string> names(fit.names.begin(),
                                       fit.names.begin() + kGyroscopeCalibrationCount);
  const std::array<double, 3> shares = GyroscopeTurnShares(fit);
  for (int i = 0; i < kGyroscopeCalibrationCount; ++i) {
    double threshold = 0.0;
    std::string words;
    if (i < kGyroscopeGainX) {
      threshold = thresholds.angle_sigma_rad;
      words = StringPrintf("%.3g rad", threshold);
    } else if (i < kGyroscopeParameterCount) {
      const double gain = std::fabs(fit.parameters[i]);
      threshold = thresholds.gain_relative_sigma * gain;
      words = StringPrintf("%.3g of the gain; the sigma is %.2g%% of it",
                           thresholds.gain_relative_sigma,
                           gain > 0.0 ? 100.0 * std::sqrt(fit.covariance(i, i)) / gain : 0.0);
    } else {
      const int k = i - kGyroscopeOffsetX;
      const double noise = std::sqrt(fit.noise_variance[k]);
      threshold = thresholds.offset_noise_fraction * noise;
      words = StringPrintf("%.3g x the %c axis's noise of %.3g %s per sample",
                           thresholds.offset_noise_fraction, "xyz"[k], noise, unit.c_str());
    }
    PoorlyDeterminedParameter entry;
    if (!JudgeParameterDetermination(i, names, fit.covariance, threshold, words,
                                     thresholds.correlation, &entry))
      continue;
    const std::string axis = GyroscopeTurnAxisOf(i, fit.effects_estimated);
    if (axis.empty()) {
      entry.suggestion = StringPrintf(
          "more static poses, or longer ones (the offsets come from every pose's mean; these %zu "
          "poses give them)",
          fit.rest_means.size());
    } else {
      const int k = axis[0] - 'x';
      const double total =
          fit.turned_about_rad[0] + fit.turned_about_rad[1] + fit.turned_about_rad[2];
      if (shares[k] >= kFairShare) {
        entry.suggestion = StringPrintf(
            "more turns about the sensor's %s axis (the session's turns went %.0f%% about %s "
            "already, %.1f of %.1f rad: the gyroscope's noise sets this sigma, which falls as one "
            "over the square root of the number of such turns)",
            axis.c_str(), 100.0 * shares[k], axis.c_str(), fit.turned_about_rad[k], total);
      } else {
        entry.suggestion = StringPrintf(
            "turns about the sensor's %s axis (tilt it so that %s is level and turn it about %s "
            "by 90 degrees or more, several times, both ways; the session's turns went %.0f%% "
            "about %s: %.1f of %.1f rad)",
            axis.c_str(), axis.c_str(), axis.c_str(), 100.0 * shares[k], axis.c_str(),
            fit.turned_about_rad[k], total);
      }
    }
    list.push_back(entry);
  }
  return list;
}

}  // namespace accelcal
