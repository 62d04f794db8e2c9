#ifndef ACCELCAL_MODELS_TRIAD_EFFECTS_OFFSET_DRIFT_H_
#define ACCELCAL_MODELS_TRIAD_EFFECTS_OFFSET_DRIFT_H_

// offset_drift_k [{unit}/s]: each axis's offset changing linearly over the session (warm-up,
// temperature), the tilt table's bias_drift_k in the triad's raw unit:
//   u_k += offset_drift_k (t - t0)
// t: the pose's mid-time, t0 the fit's time origin (the mean of the poses' mid-times, so that
// offset_k stays the offset in the middle of the session).

#include "models/triad_effect.h"

namespace accelcal {

struct TriadOffsetDriftEffect {
  static constexpr TriadEffectInfo kInfo = {
      "offset_drift",
      "{unit}/s",
      "linear change of the {axis} axis's offset over the session",
      3,
      {"_x", "_y", "_z"},
      "",
      2e-3,
      "a change of the offsets over the session's own time (a warm-up, a drift): another log's "
      "time says nothing of it; the offsets written are the session's mean"};

  template <typename T>
  static void Apply(const T* rate, const TriadPoseContext& context, TriadPoseTerms<T>* terms) {
    for (int k = 0; k < 3; ++k) terms->output_shift[k] += rate[k] * T(context.time_s);
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_EFFECTS_OFFSET_DRIFT_H_
