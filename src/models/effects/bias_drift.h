#ifndef ACCELCAL_MODELS_EFFECTS_BIAS_DRIFT_H_
#define ACCELCAL_MODELS_EFFECTS_BIAS_DRIFT_H_

// d_k [m/s^2]: each axis's bias change from the first to the last tilt-test sample (test
// only). With u_i = i/(N-1) - 1/2 (DriftCoordinate) the term has zero mean, so b_k stays
// the mean bias over the test:
//   m_k += d_k u_i

#include "models/effect.h"

namespace accelcal {

struct BiasDrift : EffectTerms {
  static constexpr EffectInfo kInfo = {
      "bias_drift",                                                        // name
      "m/s^2",                                                             // unit
      "{axis} bias change from the first to the last calibration sample",  // meaning
      Scope::kPerAxis,                                                     // scope
      ActsIn::kCalibrationTest,                                            // acts_in
      Role::kEffect,                                                       // role
      0.0,                                                                 // neutral
      0.1,                                                                 // example_size
      0,                                                                   // force_degree
      100.0};                                                              // largest_deviation

  template <typename T>
  static void AddAxisTerms(const T& drift, double drift_coordinate, AxisPolynomial<T>* output) {
    output->c[0] += drift * drift_coordinate;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_BIAS_DRIFT_H_
