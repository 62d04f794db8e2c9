#include "simulation/triad_simulator.h"

#include <cmath>

namespace accelcal {

std::vector<std::array<double, 3>> RandomPoseDirections(int count, RandomSource* random) {
  std::vector<std::array<double, 3>> directions;
  directions.reserve(count);
  while (static_cast<int>(directions.size()) < count) {
    // A normal vector normalised is uniform on the sphere.
    std::array<double, 3> d{random->StandardNormal(), random->StandardNormal(),
                            random->StandardNormal()};
    const double norm = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (norm < 1e-6) continue;
    for (double& v : d) v /= norm;
    directions.push_back(d);
  }
  return directions;
}

std::vector<std::array<double, 3>> PlanarPoseDirections(int count, int axis) {
  std::vector<std::array<double, 3>> directions;
  for (int i = 0; i < count; ++i) {
    const double angle_rad = 2.0 * M_PI * i / count;
    std::array<double, 3> d{};
    d[(axis + 1) % 3] = std::cos(angle_rad);
    d[(axis + 2) % 3] = std::sin(angle_rad);
    directions.push_back(d);
  }
  return directions;
}

std::vector<std::array<double, 3>> SixPoseDirections() {
  return {{{1, 0, 0}}, {{-1, 0, 0}}, {{0, 1, 0}}, {{0, -1, 0}}, {{0, 0, 1}}, {{0, 0, -1}}};
}

std::vector<std::array<double, 3>> SixPosesAndTiltsAwayFromXy(double leak) {
  const double h = std::sqrt(0.5);
  std::vector<std::array<double, 3>> directions = SixPoseDirections();
  for (const std::array<double, 3>& tilt : std::vector<std::array<double, 3>>{
           {{h, leak, h}}, {{-h, 0.0, h}}, {{leak, h, h}}, {{0.0, -h, h}}}) {
    const double norm = std::sqrt(tilt[0] * tilt[0] + tilt[1] * tilt[1] + tilt[2] * tilt[2]);
    directions.push_back({{tilt[0] / norm, tilt[1] / norm, tilt[2] / norm}});
  }
  return directions;
}

std::vector<TriadPoseMean> SimulateTriadPoses(const TriadSimulationOptions& options,
                                              const std::vector<std::array<double, 3>>& directions,
                                              RandomSource* random) {
  std::vector<TriadPoseMean> poses;
  poses.reserve(directions.size());
  const int n = options.samples_per_pose;
  const double duration_s = (n - 1) / options.sample_rate_hz;
  const double mean_time_s =
      0.5 * (static_cast<double>(directions.size()) - 1.0) * options.pose_spacing_s +
      0.5 * duration_s;
  for (const std::array<double, 3>& direction : directions) {
    TriadPoseMean pose;
    pose.sample_count = n;
    pose.duration_s = duration_s;
    pose.time_s = static_cast<double>(poses.size()) * options.pose_spacing_s + 0.5 * duration_s;
    TriadPoseContext context;
    context.time_s = pose.time_s - mean_time_s;
    double actual_raw[3];
    TriadPredictOutput(options.truth.data(), options.effects.data(), context, direction.data(),
                       options.gravity_mps2, actual_raw);
    for (int k = 0; k < 3; ++k) {
      // Drawn only when asked, so that the sessions of a seed are those without wander.
      if (options.pose_wander_stddev[k] > 0.0)
        actual_raw[k] += options.pose_wander_stddev[k] * random->StandardNormal();
    }
    for (int k = 0; k < 3; ++k) {
      // Welford's running mean and sum of squared deviations.
      double mean = 0.0;
      double m2 = 0.0;
      for (int i = 0; i < n; ++i) {
        const double measured = actual_raw[k] + options.noise_stddev[k] * random->StandardNormal();
        const double delta = measured - mean;
        mean += delta / (i + 1);
        m2 += delta * (measured - mean);
      }
      pose.mean[k] = mean;
      pose.variance[k] = n > 1 ? m2 / (n - 1) : 0.0;
    }
    poses.push_back(pose);
  }
  return poses;
}

}  // namespace accelcal
