#include "common/tilt_motion.h"

#include <algorithm>
#include <cmath>

namespace accelcal {

std::vector<double> TurnDirection(const std::vector<double>& theta_rad) {
  const int n = static_cast<int>(theta_rad.size());
  std::vector<double> direction(n, 0.0);
  if (n == 0) return direction;
  double anchor = theta_rad[0];
  double current = 0.0;
  int first_move = -1;
  for (int i = 0; i < n; ++i) {
    if (std::abs(theta_rad[i] - anchor) >= kTurnTolerance) {
      current = theta_rad[i] > anchor ? 1.0 : -1.0;
      anchor = theta_rad[i];
      if (first_move < 0) first_move = i;
    }
    direction[i] = current;
  }
  if (first_move > 0)
    std::fill(direction.begin(), direction.begin() + first_move, direction[first_move]);
  return direction;
}

std::vector<StaticPosition> StaticPositions(const std::vector<double>& theta_rad) {
  const int n = static_cast<int>(theta_rad.size());
  std::vector<StaticPosition> positions;
  for (int begin = 0; begin < n;) {
    int end = begin + 1;
    while (end < n && theta_rad[end] == theta_rad[begin]) ++end;
    if (end - begin >= kMinPositionSamples) positions.push_back({begin, end});
    begin = end;
  }
  return positions;
}

}  // namespace accelcal
