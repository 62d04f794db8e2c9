#ifndef ACCELCAL_MODELS_TRIAD_EFFECTS_CROSS_AXIS_H_
#define ACCELCAL_MODELS_TRIAD_EFFECTS_CROSS_AXIS_H_

// cross_axis_yx, cross_axis_zx, cross_axis_zy [rad]: the three entries below the diagonal of
// T (models/triad.h), which with the three misalignment angles above it make a full cross-axis
// matrix: a_y += cross_axis_yx w_x, a_z += cross_axis_zx w_x + cross_axis_zy w_y. Static poses
// of unknown direction cannot determine them: to first order the six off-diagonal terms are
// three non-orthogonality angles and a small rotation of the frame, and a rotation of the
// frame is absorbed by the poses' gravity directions. Registered so that discovery says so.

#include "models/triad_effect.h"

namespace accelcal {

struct TriadCrossAxisEffect {
  // Coefficient k: (row, column) of T it adds to.
  static constexpr int kRow[3] = {1, 2, 2};
  static constexpr int kColumn[3] = {0, 0, 1};
  static constexpr TriadEffectInfo kInfo = {
      "cross_axis",
      "rad",
      "entry below T's diagonal, a cross-axis term beyond the three misalignment angles",
      3,
      {"_yx", "_zx", "_zy"},
      "a rotation of the sensor frame, absorbed by the poses' unknown gravity directions",
      1e-3};

  template <typename T>
  static void Apply(const T* entry, const TriadPoseContext& /*context*/, TriadPoseTerms<T>* terms) {
    for (int k = 0; k < 3; ++k) terms->frame[kRow[k]][kColumn[k]] += entry[k];
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_TRIAD_EFFECTS_CROSS_AXIS_H_
