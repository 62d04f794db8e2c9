#ifndef ACCELCAL_TESTS_HAND_HELD_SESSION_H_
#define ACCELCAL_TESTS_HAND_HELD_SESSION_H_

// Simulated hand-held sessions of a triad in counts, for the tests of the streamed static
// detector and allan (issue 36, item 2): 415 counts per m/s^2 about offsets near 32768, holds of
// 4 s in random directions at least 30 degrees apart, 1.5 s turns, 100 Hz, and imu_tk's text
// layout `t x y z` of such a log.

#include <cmath>
#include <string>
#include <vector>

#include "common/format.h"
#include "models/triad.h"
#include "simulation/random.h"
#include "simulation/triad_log_simulator.h"

namespace accelcal {
namespace testing {

inline TriadLogSimulationOptions HandHeldTriad(double noise_counts = 3.0) {
  TriadLogSimulationOptions options;
  options.truth = TriadParametersWithOffset(32808.0, 32743.0, 32778.0);
  for (int k = 0; k < 3; ++k) options.truth[kTriadGainX + k] = 1.0 / 415.0;
  options.noise_stddev = {noise_counts, noise_counts, noise_counts};
  return options;
}

// `holds` holds of 4 s; with `fourfold`, the noise of hold p is 2^(p mod 3) times noise_counts.
inline TriadSession HandHeldSession(uint64_t seed, int holds, double noise_counts = 3.0,
                                    bool fourfold = false) {
  RandomSource random(seed);
  std::vector<TriadHold> chosen = RandomSeparatedHolds(holds, 4.0, 30.0, &random);
  if (fourfold) {
    for (size_t p = 0; p < chosen.size(); ++p) chosen[p].noise_scale = std::pow(2.0, p % 3);
  }
  return SimulateTriadSession(HandHeldTriad(noise_counts), chosen, &random);
}

// 40 orientations passed through without stopping (2 s turns): a log that never rests.
inline TriadLog NeverRestingLog(uint64_t seed) {
  RandomSource random(seed);
  TriadLogSimulationOptions options = HandHeldTriad();
  options.turn_s = 2.0;
  return SimulateTriadSession(options, RandomSeparatedHolds(40, 0.0, 30.0, &random), &random).log;
}

// `log` as imu_tk's text, t = 0.01 (i + 1) s; samples [gap_first, gap_first + gap_count) left out
// (a pause in the recording).
inline std::string ImuTkText(const TriadLog& log, size_t gap_first = 0, size_t gap_count = 0) {
  std::string text;
  for (size_t i = 0; i < log.size(); ++i) {
    if (i >= gap_first && i < gap_first + gap_count) continue;
    text += RoundTripDouble(0.01 * static_cast<double>(i + 1)) +
            StringPrintf(" %.0f %.0f %.0f\n", log.output[i][0], log.output[i][1], log.output[i][2]);
  }
  return text;
}

}  // namespace testing
}  // namespace accelcal

#endif  // ACCELCAL_TESTS_HAND_HELD_SESSION_H_
