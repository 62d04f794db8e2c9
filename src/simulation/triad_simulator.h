#ifndef ACCELCAL_SIMULATION_TRIAD_SIMULATOR_H_
#define ACCELCAL_SIMULATION_TRIAD_SIMULATOR_H_

// Static poses of a triad (models/triad.h), simulated: in pose p the specific force is
// g n_p for a unit gravity direction n_p, the triad outputs u = K^-1 T^-1 g n_p + b
// (TriadRawOutput, the same expression the residuals invert), and every sample adds white
// Gaussian noise of a known standard deviation per axis, in counts. Each pose is summarised
// as the mean and sample variance of its samples (common/triad_log.h), as the static
// detector summarises an interval of a real log.

#include <array>
#include <vector>

#include "common/triad_log.h"
#include "models/triad.h"
#include "simulation/random.h"

namespace accelcal {

struct TriadSimulationOptions {
  TriadParameters truth{};
  double gravity_mps2 = 9.81;
  int samples_per_pose = 100;
  std::array<double, 3> noise_stddev{{3.0, 3.0, 3.0}};  // per sample, in counts
};

// `count` directions drawn uniformly on the unit sphere.
std::vector<std::array<double, 3>> RandomPoseDirections(int count, RandomSource* random);

// One pose per direction (unit vectors), with its samples' mean and sample variance.
std::vector<TriadPoseMean> SimulateTriadPoses(const TriadSimulationOptions& options,
                                              const std::vector<std::array<double, 3>>& directions,
                                              RandomSource* random);

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_TRIAD_SIMULATOR_H_
