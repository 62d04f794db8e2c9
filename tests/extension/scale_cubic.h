#ifndef ACCELCAL_TESTS_EXTENSION_SCALE_CUBIC_H_
#define ACCELCAL_TESTS_EXTENSION_SCALE_CUBIC_H_

// An effect beyond the spec, added the way docs/extending.md describes: this file plus one
// registration line (registered_effects.h). The third-order scale term of IEEE Std 1293's
// accelerometer model, K3 in its notation, per axis, in the test and in the run:
//
//   m_k += k3_k f_along_k^3        [k3_k] = 1/(m/s^2)^2
//
// Nothing else in the library is edited: the catalogue gains scale_cubic_x and
// scale_cubic_y, the simulator and scenario files accept them, both residuals take them as
// blocks, dead reckoning differentiates through them, the run's inverse adds Newton steps
// (force_degree 3), the compressed tilt residual sees that sin^3 is outside its basis and
// the joint solve falls back to per-sample residuals, and discovery tries them as
// candidates. extension_test.cc checks each of these.

#include "models/effect.h"

namespace accelcal {

struct ScaleCubic : EffectTerms {
  static constexpr EffectInfo kInfo = {
      "scale_cubic",                                               // name
      "1/(m/s^2)^2",                                               // unit
      "third-order scale term of the {axis} axis (IEEE 1293 K3)",  // meaning
      Scope::kPerAxis,                                             // scope
      ActsIn::kBoth,                                               // acts_in
      Role::kEffect,                                               // role
      0.0,                                                         // neutral
      // At g = 9.8 m/s^2 this is 0.19 m/s^2 at the table's extremes, about 7 sigma on the
      // course-sized test once the part that scale_k absorbs is removed.
      2e-4,  // example_size
      3};    // force_degree

  template <typename T>
  static void AddAxisTerms(const T& k3, double /*drift_coordinate*/, AxisPolynomial<T>* output) {
    output->c[3] += k3;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_TESTS_EXTENSION_SCALE_CUBIC_H_
