#include "estimation/triad/triad_initial_guess.h"

#include <algorithm>
#include <array>

namespace accelcal {

TriadParameters TriadStartFromPoses(const std::vector<TriadPoseMean>& poses, double gravity_mps2) {
  TriadParameters start = TriadParametersWithOffset(0.0, 0.0, 0.0);
  std::array<double, 3> range{};
  for (int k = 0; k < 3; ++k) {
    double lowest = poses.front().mean[k];
    double highest = lowest;
    for (const TriadPoseMean& pose : poses) {
      lowest = std::min(lowest, pose.mean[k]);
      highest = std::max(highest, pose.mean[k]);
    }
    start[kTriadOffsetX + k] = 0.5 * (lowest + highest);
    range[k] = highest - lowest;
  }
  // An axis the poses barely turn (all gravity near a plane) says nothing of its gain; it
  // borrows the widest axis's, as the axes of one triad have similar gains.
  const double widest = *std::max_element(range.begin(), range.end());
  for (int k = 0; k < 3; ++k) {
    const double used = range[k] >= 0.5 * widest ? range[k] : widest;
    if (used > 0.0) start[kTriadGainX + k] = 2.0 * gravity_mps2 / used;
  }
  return start;
}

}  // namespace accelcal
