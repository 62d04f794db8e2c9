#ifndef ACCELCAL_COMMON_LANDMARK_CHECKS_H_
#define ACCELCAL_COMMON_LANDMARK_CHECKS_H_

// The one check every source of landmarks passes (puntos.mat, landmarks.csv, a scenario's
// listed landmarks): at least one, names unique, and no two at the same place. Two
// landmarks at one position make "which one did the vehicle reach" unanswerable, and a
// decision between them would be decided by the order they were listed in.

#include <cmath>
#include <string>
#include <vector>

#include "common/format.h"
#include "common/measurements.h"
#include "common/status.h"

namespace accelcal {

inline Status CheckLandmarks(const std::vector<Landmark>& landmarks) {
  if (landmarks.empty()) return Status::Error("no landmarks are given");
  for (size_t a = 0; a < landmarks.size(); ++a) {
    if (!std::isfinite(landmarks[a].x_m) || !std::isfinite(landmarks[a].y_m)) {
      return Status::Error("landmark '" + landmarks[a].name + "' is not finite");
    }
    for (size_t b = 0; b < a; ++b) {
      if (landmarks[a].name == landmarks[b].name) {
        return Status::Error("landmark '" + landmarks[a].name + "' is listed twice");
      }
      // Closer than a millimetre is the same place for a dead-reckoned vehicle.
      if (std::hypot(landmarks[a].x_m - landmarks[b].x_m, landmarks[a].y_m - landmarks[b].y_m) <
          1e-3) {
        return Status::Error(StringPrintf(
            "landmarks '%s' and '%s' are both at (%.6g, %.6g) m, so no data can tell them apart; "
            "remove one or correct its position",
            landmarks[b].name.c_str(), landmarks[a].name.c_str(), landmarks[a].x_m,
            landmarks[a].y_m));
      }
    }
  }
  return Status::Ok();
}

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_LANDMARK_CHECKS_H_
