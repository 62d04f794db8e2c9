#ifndef ACCELCAL_SIMULATION_RANDOM_H_
#define ACCELCAL_SIMULATION_RANDOM_H_

// A random source whose output depends only on its seed, on any machine and standard
// library: std::normal_distribution is implementation-defined, so simulated data made
// with it would differ between libstdc++ and libc++. This uses xoshiro256++ (seeded by
// splitmix64) and the polar Box-Muller transform, both fully specified here.

#include <cstdint>

namespace accelcal {

class RandomSource {
 public:
  // `stream` separates independent sequences from one seed (e.g. Monte Carlo trials),
  // so that a trial's data does not depend on how trials are spread over threads.
  explicit RandomSource(uint64_t seed, uint64_t stream = 0);

  uint64_t NextUint64();
  double Uniform();         // in [0, 1), 53 random bits
  double StandardNormal();  // N(0, 1)

 private:
  uint64_t state_[4];
  bool has_spare_normal_ = false;
  double spare_normal_ = 0.0;
};

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_RANDOM_H_
