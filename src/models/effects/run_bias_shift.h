#ifndef ACCELCAL_MODELS_EFFECTS_RUN_BIAS_SHIFT_H_
#define ACCELCAL_MODELS_EFFECTS_RUN_BIAS_SHIFT_H_

// r_k [m/s^2]: each axis's bias in the vehicle run minus its bias in the tilt test (run
// only, so observable only through a landmark):
//   m_k += r_k

#include "models/effect.h"

namespace accelcal {

struct RunBiasShift : EffectTerms {
  static constexpr EffectInfo kInfo = {
      "run_bias_shift",                                                     // name
      "m/s^2",                                                              // unit
      "{axis} bias in the vehicle run minus bias in the calibration test",  // meaning
      Scope::kPerAxis,                                                      // scope
      ActsIn::kVehicleRun,                                                  // acts_in
      Role::kEffect,                                                        // role
      0.0,                                                                  // neutral
      0.02,                                                                 // example_size
      0,                                                                    // force_degree
      100.0};                                                               // largest_deviation

  template <typename T>
  static void AddAxisTerms(const T& shift, double /*drift_coordinate*/, AxisPolynomial<T>* output) {
    output->c[0] += shift;
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_EFFECTS_RUN_BIAS_SHIFT_H_
