#ifndef ACCELCAL_MODELS_GYROSCOPE_EFFECTS_TIME_OFFSET_H_
#define ACCELCAL_MODELS_GYROSCOPE_EFFECTS_TIME_OFFSET_H_

// gyroscope_time_offset [s]: the gyroscope's samples lag the accelerometer's by d (a sample of
// row j holds the rate at t_j - d: different filter delays, buffers, two streams joined), so
// the output at the accelerometer's time is, to first order in d,
//   u_k += d du_k/dt
// du/dt: the output's rate of change at the sample (central differences). Its effect on a turn
// integrated from rest to rest telescopes to d (w_end - R^T w_start): it shows where a turn's
// window starts or ends in motion (a stop within a sample, a static detector's tight margin) and
// in the poses next to such a turn (the rest residual's context is the pose's mean output rate)
// and nowhere else: a session whose turns start and end at rest leaves it undetermined. First
// order: for offsets within a sample or so (docs/gyroscope.md: at 2 ms in gyroscope_study's design
// sigma / spread 1.00, bias -0.26 sigma; at 4 ms the second-order term biases it by -1.4 sigma).

#include "models/gyroscope_effect.h"

namespace accelcal {

struct GyroscopeTimeOffsetEffect {
  static constexpr GyroscopeEffectInfo kInfo = {
      "time_offset",
      "s",
      "the gyroscope's samples lag the accelerometer's (positive) or lead them by this time",
      "log both sensors from one clock (one driver, the sensor's own time stamps), or let the "
      "sensor rest a moment longer at each pose so that no turn starts or ends in motion",
      1,
      {""},
      GyroscopeEffectStage::kOutput,
      false,
      false,
      {2e-3},
      "the two streams' alignment belongs to the logging chain of the session (buffers, host "
      "times): `apply` corrects each sample at the time it was logged"};

  template <typename T>
  static void Apply(const T* lag, const GyroscopeSampleContext<T>& context,
                    GyroscopeRateTerms<T>* terms) {
    if (context.output_rate == nullptr) return;
    for (int k = 0; k < 3; ++k) terms->output_shift[k] += lag[0] * context.output_rate[k];
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_MODELS_GYROSCOPE_EFFECTS_TIME_OFFSET_H_
