#include "estimation/triad/triad_determination.h"

#include <algorithm>
#include <cmath>

#include "common/format.h"

namespace accelcal {
namespace {

const char kAxes[] = "xyz";

// The two axes an angle couples (models/triad.h: misalignment_yz tilts y towards x, _zy z
// towards x, _zx z towards y).
void CoupledAxes(int angle, int* first, int* second) {
  static const int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  *first = kPairs[angle][0];
  *second = kPairs[angle][1];
}

// What the poses' fitted directions reach along what determines parameter p, and the poses
// that would determine it.
std::string Suggestion(const TriadMlResult& ml, int p) {
  if (p < kTriadGainX) {
    int j = 0;
    int k = 0;
    CoupledAxes(p, &j, &k);
    double largest = 0.0;
    for (const auto& n : ml.directions) largest = std::max(largest, std::fabs(n[j] * n[k]));
    return StringPrintf(
        "poses with gravity between +-%c and +-%c (tilted 45 degrees in the %c-%c plane, "
        "|n_%c n_%c| near 0.5; these poses reach %.2g)",
        kAxes[j], kAxes[k], kAxes[j], kAxes[k], kAxes[j], kAxes[k], largest);
  }
  const int k = (p - kTriadGainX) % 3;
  double low = 1.0;
  double high = -1.0;
  for (const auto& n : ml.directions) {
    low = std::min(low, n[k]);
    high = std::max(high, n[k]);
  }
  if (p < kTriadOffsetX) {
    return StringPrintf(
        "poses with the %c axis near +g or -g (|n_%c| near 1; these poses reach %.2g)", kAxes[k],
        kAxes[k], std::max(std::fabs(low), std::fabs(high)));
  }
  return StringPrintf(
      "poses with the %c axis near +g AND near -g (n_%c near +1 and -1; these poses reach "
      "%.2g to %.2g)",
      kAxes[k], kAxes[k], low, high);
}

}  // namespace

std::vector<TriadPoorlyDetermined> PoorlyDeterminedTriadParameters(
    const TriadMlResult& ml, const std::string& unit, const TriadDeterminationOptions& options) {
  std::vector<TriadPoorlyDetermined> list;
  const auto& infos = TriadParameterInfos();
  for (int p = 0; p < kTriadParameterCount; ++p) {
    TriadPoorlyDetermined entry;
    entry.index = p;
    entry.parameter = infos[p].name;
    entry.sigma = ml.stddev[p];
    std::string threshold_words;
    if (p < kTriadGainX) {
      entry.threshold = options.angle_sigma_rad;
      threshold_words = StringPrintf("%.3g rad", entry.threshold);
    } else if (p < kTriadOffsetX) {
      entry.threshold = options.gain_relative_sigma * std::fabs(ml.parameters[p]);
      threshold_words = StringPrintf("%.3g of the gain", options.gain_relative_sigma);
    } else {
      const int k = p - kTriadOffsetX;
      const double noise = std::sqrt(ml.noise_variance[k]);
      entry.threshold = options.offset_noise_fraction * noise;
      threshold_words = StringPrintf("%.3g x the %c axis's noise of %.3g %s per sample",
                                     options.offset_noise_fraction, kAxes[k], noise, unit.c_str());
    }
    entry.sigma_over_threshold = !(entry.sigma <= entry.threshold);
    for (int q = 0; q < kTriadParameterCount; ++q) {
      if (q == p) continue;
      const double scale = ml.stddev[p] * ml.stddev[q];
      const double rho = scale > 0.0 ? ml.covariance[p][q] / scale : 0.0;
      if (std::fabs(rho) > options.correlation)
        entry.correlated_with.push_back({infos[q].name, rho});
    }
    if (!entry.sigma_over_threshold && entry.correlated_with.empty()) continue;
    if (entry.sigma_over_threshold) {
      entry.reason = StringPrintf("sigma %.3g > %.3g (%s)", entry.sigma, entry.threshold,
                                  threshold_words.c_str());
    }
    if (!entry.correlated_with.empty()) {
      std::string with;
      for (const TriadCorrelatedParameter& other : entry.correlated_with) {
        with += StringPrintf("%s%s (%+.4f)", with.empty() ? "" : ", ", other.parameter.c_str(),
                             other.correlation);
      }
      entry.reason +=
          StringPrintf("%scorrelation beyond +-%g with %s", entry.reason.empty() ? "" : "; ",
                       options.correlation, with.c_str());
    }
    entry.suggestion = Suggestion(ml, p);
    list.push_back(entry);
  }
  return list;
}

std::string PoorlyDeterminedNames(const std::vector<TriadPoorlyDetermined>& list) {
  std::string names;
  for (const TriadPoorlyDetermined& entry : list)
    names += (names.empty() ? "" : ", ") + entry.parameter;
  return names;
}

}  // namespace accelcal
