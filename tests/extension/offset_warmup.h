#ifndef ACCELCAL_TESTS_EXTENSION_OFFSET_WARMUP_H_
#define ACCELCAL_TESTS_EXTENSION_OFFSET_WARMUP_H_

// A research project's own triad effect (docs/extending.md): each axis's offset following a
// warm-up, quadratic in time about the session's middle, in the triad's raw unit:
//   u_k += offset_warmup_k (t - t0)^2
// t: the pose's mid-time, t0 the fit's time origin. It is the whole of the effect: registered
// by one line (registered_triad_effects.h), it reaches the ML fit, the simulator, the pose
// residual and discovery's candidates with no other change.

#include "models/triad_effect.h"

namespace accelcal {

struct TriadOffsetWarmupEffect {
  static constexpr TriadEffectInfo kInfo = {
      "offset_warmup",
      "{unit}/s^2",
      "the {axis} axis's offset curving over the session (warm-up): quadratic in time",
      3,
      {"_x", "_y", "_z"},
      "",
      2e-5,
      "a change of the offsets over the session's own time: another log's time says nothing of "
      "it"};

  template <typename T>
  static void Apply(const T* curvature, const TriadPoseContext& context, TriadPoseTerms<T>* terms) {
    const T t(context.time_s);
    for (int k = 0; k < 3; ++k) terms->output_shift[k] += curvature[k] * t * t;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_TESTS_EXTENSION_OFFSET_WARMUP_H_
