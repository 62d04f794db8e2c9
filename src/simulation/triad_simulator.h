#ifndef ACCELCAL_SIMULATION_TRIAD_SIMULATOR_H_
#define ACCELCAL_SIMULATION_TRIAD_SIMULATOR_H_

// Static poses of a triad (models/triad.h), simulated: in pose p the specific force is
// g n_p for a unit gravity direction n_p, the triad outputs what TriadPredictOutput says
// (models/triad_effect_list.h: the 9 parameters and any effect's coefficients, zero by
// default; the same expression the residuals invert), pose p is held at time p * spacing
// (referred, like the fit's, to the mean of the poses' times), each pose's output may be
// shifted by a per-pose random offset (bias wander between poses, none by default), and every
// sample adds white Gaussian noise of a known standard deviation per axis, in counts. Each pose is
// summarised as the mean and sample variance of its samples (common/triad_log.h), as the static
// detector summarises an interval of a real log.

#include <array>
#include <vector>

#include "common/triad_log.h"
#include "models/triad.h"
#include "models/triad_effect_list.h"
#include "simulation/random.h"

namespace accelcal {

struct TriadSimulationOptions {
  TriadParameters truth{};
  TriadEffectCoefficients effects{};  // models/triad_effect_list.h's units
  double gravity_mps2 = 9.81;
  int samples_per_pose = 100;
  std::array<double, 3> noise_stddev{{3.0, 3.0, 3.0}};  // per sample, in counts
  double sample_rate_hz = 100.0;
  double pose_spacing_s = 10.0;  // from one pose's start to the next's
  // Standard deviation of each pose's offset (counts), drawn anew per pose: the pose means
  // scatter more than their samples' white noise says, as coloured noise makes them.
  std::array<double, 3> pose_wander_stddev{};
};

// `count` directions drawn uniformly on the unit sphere.
std::vector<std::array<double, 3>> RandomPoseDirections(int count, RandomSource* random);

// `count` directions evenly spaced on the great circle orthogonal to `axis` (0, 1, 2: x, y,
// z): the sensor turned about one of its axes only, a pose set that cannot determine a triad.
std::vector<std::array<double, 3>> PlanarPoseDirections(int count, int axis);

// The six directions +x, -x, +y, -y, +z, -z: each axis up and down once (imucal's six holds).
std::vector<std::array<double, 3>> SixPoseDirections();

// SixPoseDirections and four 45-degree tilts, two in the x-z plane and two in the y-z plane,
// each leaning `leak` towards the x-y plane before normalising (|n_x n_y| <= about leak / 1.4):
// ten poses that see misalignment_yz, which couples x and y, only through `leak`.
std::vector<std::array<double, 3>> SixPosesAndTiltsAwayFromXy(double leak);

// One pose per direction (unit vectors), with its samples' mean and sample variance.
std::vector<TriadPoseMean> SimulateTriadPoses(const TriadSimulationOptions& options,
                                              const std::vector<std::array<double, 3>>& directions,
                                              RandomSource* random);

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_TRIAD_SIMULATOR_H_
