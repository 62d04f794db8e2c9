#ifndef ACCELCAL_MODELS_EFFECTS_NONORTHOGONALITY_H_
#define ACCELCAL_MODELS_EFFECTS_NONORTHOGONALITY_H_

// eps [rad]: the y sensing axis tilted toward x, in the test and the run:
//   f_along_x = fx,  f_along_y = fy cos(eps) + fx sin(eps)
// undone by fx = f_along_x, fy = (f_along_y - fx sin(eps)) / cos(eps).

#include <cmath>

#include "models/effect.h"

namespace accelcal {

struct Nonorthogonality : EffectTerms {
  static constexpr EffectInfo kInfo = {"nonorthogonality",                // name
                                       "rad",                             // unit
                                       "y sensing axis tilted toward x",  // meaning
                                       Scope::kShared,                    // scope
                                       ActsIn::kBoth,                     // acts_in
                                       Role::kEffect,                     // role
                                       0.0,                               // neutral
                                       0.004,                             // example_size
                                       0,                                 // force_degree
                                       0.5};                              // largest_deviation

  template <typename T>
  static void Project(const T& eps_rad, T* along_x, T* along_y) {
    using std::cos;
    using std::sin;
    *along_y = *along_y * cos(eps_rad) + *along_x * sin(eps_rad);
  }

  template <typename T>
  static void Unproject(const T& eps_rad, T* x, T* y) {
    using std::cos;
    using std::sin;
    *y = (*y - *x * sin(eps_rad)) / cos(eps_rad);
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_NONORTHOGONALITY_H_
