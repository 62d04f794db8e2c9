#ifndef ACCELCAL_COMMON_LANDMARK_CHECKS_H_
#define ACCELCAL_COMMON_LANDMARK_CHECKS_H_

// The one check every source of landmarks passes (puntos.mat, landmarks.csv, a scenario's
// listed landmarks): at least one, names unique, and no two at the same place. Two
// landmarks at one position make "which one did the vehicle reach" unanswerable, and a
// decision between them would be decided by the order they were listed in.

#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "common/format.h"
#include "common/measurements.h"
#include "common/status.h"

namespace accelcal {

// Names are compared through a hash set and places through a grid of 1 mm cells (each
// landmark against the landmarks of its own and the eight neighbouring cells), so a file of
// 10^5 landmarks is checked in milliseconds, not in the minute a comparison of every pair
// takes.
inline Status CheckLandmarks(const std::vector<Landmark>& landmarks) {
  if (landmarks.empty()) return Status::Error("no landmarks are given");
  // Closer than a millimetre is the same place for a dead-reckoned vehicle.
  constexpr double kSamePlaceM = 1e-3;
  std::unordered_set<std::string> names;
  std::unordered_map<uint64_t, std::vector<size_t>> cells;
  auto cell_of = [&](long long i, long long j) {
    return (static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ull) ^ static_cast<uint64_t>(j);
  };
  for (size_t a = 0; a < landmarks.size(); ++a) {
    const Landmark& landmark = landmarks[a];
    // Beyond 1e12 m no vehicle goes; the bound also keeps the cell indices in range.
    if (!std::isfinite(landmark.x_m) || !std::isfinite(landmark.y_m) ||
        std::abs(landmark.x_m) > 1e12 || std::abs(landmark.y_m) > 1e12) {
      return Status::Error("landmark '" + landmark.name +
                           "' is not a finite position within 1e12 m");
    }
    if (!names.insert(landmark.name).second) {
      return Status::Error("landmark '" + landmark.name + "' is listed twice");
    }
    const long long i = static_cast<long long>(std::floor(landmark.x_m / kSamePlaceM));
    const long long j = static_cast<long long>(std::floor(landmark.y_m / kSamePlaceM));
    for (long long di = -1; di <= 1; ++di) {
      for (long long dj = -1; dj <= 1; ++dj) {
        const auto found = cells.find(cell_of(i + di, j + dj));
        if (found == cells.end()) continue;
        for (const size_t b : found->second) {
          if (std::hypot(landmark.x_m - landmarks[b].x_m, landmark.y_m - landmarks[b].y_m) <
              kSamePlaceM) {
            return Status::Error(StringPrintf(
                "landmarks '%s' and '%s' are both at (%.6g, %.6g) m, so no data can tell them "
                "apart; remove one or correct its position",
                landmarks[b].name.c_str(), landmark.name.c_str(), landmark.x_m, landmark.y_m));
          }
        }
      }
    }
    cells[cell_of(i, j)].push_back(a);
  }
  return Status::Ok();
}

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_LANDMARK_CHECKS_H_
