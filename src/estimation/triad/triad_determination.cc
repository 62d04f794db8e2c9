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
  std::vector<std::string> names;
  Eigen::MatrixXd covariance(kTriadParameterCount, kTriadParameterCount);
  for (int p = 0; p < kTriadParameterCount; ++p) {
    names.push_back(infos[p].name);
    for (int q = 0; q < kTriadParameterCount; ++q) covariance(p, q) = ml.covariance[p][q];
  }
  for (int p = 0; p < kTriadParameterCount; ++p) {
    double threshold = 0.0;
    std::string threshold_words;
    if (p < kTriadGainX) {
      threshold = options.angle_sigma_rad;
      threshold_words = StringPrintf("%.3g rad", threshold);
    } else if (p < kTriadOffsetX) {
      threshold = options.gain_relative_sigma * std::fabs(ml.parameters[p]);
      threshold_words = StringPrintf("%.3g of the gain", options.gain_relative_sigma);
    } else {
      const int k = p - kTriadOffsetX;
      const double noise = std::sqrt(ml.noise_variance[k]);
      threshold = options.offset_noise_fraction * noise;
      threshold_words = StringPrintf("%.3g x the %c axis's noise of %.3g %s per sample",
                                     options.offset_noise_fraction, kAxes[k], noise, unit.c_str());
    }
    TriadPoorlyDetermined entry;
    if (!JudgeParameterDetermination(p, names, covariance, threshold, threshold_words,
                                     options.correlation, &entry))
      continue;
    entry.suggestion = Suggestion(ml, p);
    list.push_back(entry);
  }
  return list;
}

}  // namespace accelcal
