#ifndef ACCELCAL_SIMULATION_TRIAD_SIMULATOR_H_
#define ACCELCAL_SIMULATION_TRIAD_SIMULATOR_H_

// Static poses of a triad (models/triad.h), simulated: in pose p the specific force is
// g n_p for a unit gravity direction n_p, the triad outputs u = K^-1 (w + k2 w^2) + b with
// w = T^-1 g n_p (TriadRawOutput, the same expression the residuals invert; k2 the
// second-order scale terms, zero by default), and every sample adds white
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
  TriadScaleNonlinearity scale_nonlinearity{};  // k2_k, 1/(m/s^2)
  double gravity_mps2 = 9.81;
  int samples_per_pose = 100;
  std::array<double, 3> noise_stddev{{3.0, 3.0, 3.0}};  // per sample, in counts
};

// `count` directions drawn uniformly on the unit sphere.
std::vector<std::array<double, 3>> RandomPoseDirections(int count, RandomSource* random);

// `count` directions evenly spaced on the great circle orthogonal to `axis` (0, 1, 2: x, y,
// z): the sensor turned about one of its axes only, a pose set that cannot determine a triad.
std::vector<std::array<double, 3>> PlanarPoseDirections(int count, int axis);

// The six directions +x, -x, +y, -y, +z, -z: each axis up and down once (imucal's six holds).
std::vector<std::array<double, 3>> SixPoseDirections();

// One pose per direction (unit vectors), with its samples' mean and sample variance.
std::vector<TriadPoseMean> SimulateTriadPoses(const TriadSimulationOptions& options,
                                              const std::vector<std::array<double, 3>>& directions,
                                              RandomSource* random);

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_TRIAD_SIMULATOR_H_
