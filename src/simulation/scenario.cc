#include "simulation/scenario.h"

#include <algorithm>
#include <cmath>

#include "models/dead_reckoning.h"
#include "simulation/random.h"

namespace accelcal {

void TrueRunAcceleration(const RunProfile& profile, std::vector<double>* timestamp_s,
                         std::vector<double>* acceleration_x, std::vector<double>* acceleration_y) {
  const int count = static_cast<int>(std::llround(profile.duration_s / profile.dt_s));
  timestamp_s->resize(count);
  for (int j = 0; j < count; ++j) (*timestamp_s)[j] = j * profile.dt_s;
  if (!profile.csv_acceleration_x.empty()) {
    *acceleration_x = profile.csv_acceleration_x;
    *acceleration_y = profile.csv_acceleration_y;
    return;
  }
  std::vector<double> raw_x(count);
  std::vector<double> raw_y(count);
  size_t segment = 0;
  double segment_end = profile.segments[0].duration_s;
  for (int j = 0; j < count; ++j) {
    // A sample on a boundary belongs to the segment that starts there.
    while (segment + 1 < profile.segments.size() &&
           (*timestamp_s)[j] >= segment_end - 1e-9 * profile.dt_s) {
      ++segment;
      segment_end += profile.segments[segment].duration_s;
    }
    raw_x[j] = profile.segments[segment].acceleration_x;
    raw_y[j] = profile.segments[segment].acceleration_y;
  }
  // Centred moving average over `window` samples, truncated at the ends.
  const int half = static_cast<int>(std::llround(0.5 * profile.smoothing_s / profile.dt_s));
  acceleration_x->resize(count);
  acceleration_y->resize(count);
  std::vector<double> prefix_x(count + 1, 0.0);
  std::vector<double> prefix_y(count + 1, 0.0);
  for (int j = 0; j < count; ++j) {
    prefix_x[j + 1] = prefix_x[j] + raw_x[j];
    prefix_y[j + 1] = prefix_y[j] + raw_y[j];
  }
  for (int j = 0; j < count; ++j) {
    const int begin = std::max(0, j - half);
    const int end = std::min(count, j + half + 1);
    (*acceleration_x)[j] = half == 0 ? raw_x[j] : (prefix_x[end] - prefix_x[begin]) / (end - begin);
    (*acceleration_y)[j] = half == 0 ? raw_y[j] : (prefix_y[end] - prefix_y[begin]) / (end - begin);
  }
}

SimulatedData SimulateScenario(const Scenario& scenario, uint64_t seed, uint64_t trial) {
  SimulatedData data;
  data.test = SimulateTiltTest(scenario.tilt, scenario.truth, seed, trial, &data.outlier_indices_x,
                               &data.outlier_indices_y);
  std::vector<double> timestamp_s;
  TrueRunAcceleration(scenario.run, &timestamp_s, &data.true_acceleration_x,
                      &data.true_acceleration_y);
  data.run = SimulateVehicleRun(timestamp_s, data.true_acceleration_x, data.true_acceleration_y,
                                scenario.truth, seed, trial);
  RunConditions& conditions = data.conditions;
  conditions.initial_position_x_m = scenario.initial_position_x_m;
  conditions.initial_position_y_m = scenario.initial_position_y_m;
  conditions.initial_velocity_x_mps = scenario.initial_velocity_x_mps;
  conditions.initial_velocity_y_mps = scenario.initial_velocity_y_mps;
  conditions.noise_variance_x = scenario.truth.stated_noise_variance_x;
  conditions.noise_variance_y = scenario.truth.stated_noise_variance_y;
  conditions.has_gravity = true;
  conditions.gravity_mps2 = scenario.truth.gravity_mps2;

  AxisKinematics<double> x{scenario.initial_position_x_m, scenario.initial_velocity_x_mps};
  AxisKinematics<double> y{scenario.initial_position_y_m, scenario.initial_velocity_y_mps};
  for (size_t j = 1; j < timestamp_s.size(); ++j) {
    TrapezoidalStep(scenario.run.dt_s, data.true_acceleration_x[j - 1], data.true_acceleration_x[j],
                    &x);
    TrapezoidalStep(scenario.run.dt_s, data.true_acceleration_y[j - 1], data.true_acceleration_y[j],
                    &y);
  }
  data.true_endpoint = Eigen::Vector2d(x.position, y.position);

  if (scenario.landmarks.decoys) {
    // Decoys at min_distance to 2 min_distance from the true endpoint and at least
    // min_distance from each other; the true endpoint hides among them under a letter.
    RandomSource random(seed ^ 0x6C616E646D61726Bull, trial);
    const double d = scenario.landmarks.decoy_min_distance_m;
    std::vector<Eigen::Vector2d> points = {data.true_endpoint};
    for (int k = 0; k < scenario.landmarks.decoy_count; ++k) {
      Eigen::Vector2d candidate;
      for (int attempt = 0; attempt < 10000; ++attempt) {
        const double angle = 2.0 * M_PI * random.Uniform();
        const double radius = d * (1.0 + random.Uniform() * (1.0 + attempt / 100.0));
        candidate = data.true_endpoint + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
        bool far_enough = true;
        for (const Eigen::Vector2d& point : points)
          far_enough = far_enough && (candidate - point).norm() >= d;
        if (far_enough) break;
      }
      points.push_back(candidate);
    }
    const int true_slot = static_cast<int>(random.Uniform() * points.size());
    std::swap(points[0], points[true_slot]);
    for (size_t k = 0; k < points.size(); ++k) {
      data.landmarks.push_back(
          {std::string(1, static_cast<char>('A' + k)), points[k].x(), points[k].y()});
    }
  } else {
    data.landmarks = scenario.landmarks.listed;
  }
  double nearest = HUGE_VAL;
  for (const Landmark& landmark : data.landmarks) {
    const double distance =
        (Eigen::Vector2d(landmark.x_m, landmark.y_m) - data.true_endpoint).norm();
    if (distance < nearest) {
      nearest = distance;
      data.reached_landmark = landmark.name;
    }
  }
  data.reached_distance_m = nearest;
  return data;
}

nlohmann::json TruthJson(const Scenario& scenario, const SimulatedData& data, uint64_t seed) {
  using nlohmann::json;
  json parameters = json::object();
  json units = json::object();
  for (const ParameterInfo& info : ParameterCatalogue()) {
    parameters[info.name] = scenario.truth.parameters[info.parameter];
    units[info.name] = info.unit;
  }
  json landmarks = json::array();
  for (const Landmark& landmark : data.landmarks) {
    landmarks.push_back({{"name", landmark.name}, {"x", landmark.x_m}, {"y", landmark.y_m}});
  }
  json truth = {
      {"scenario", scenario.name},
      {"seed", seed},
      {"parameters", parameters},
      {"units", units},
      {"gravity_mps2", scenario.truth.gravity_mps2},
      {"stated_noise_variance",
       {{"x", scenario.truth.stated_noise_variance_x},
        {"y", scenario.truth.stated_noise_variance_y}}},
      {"true_noise_variance",
       {{"x", scenario.truth.TrueNoiseVarianceX()}, {"y", scenario.truth.TrueNoiseVarianceY()}}},
      {"tilt_samples", data.test.size()},
      {"run_samples", data.run.size()},
      {"run_dt_s", scenario.run.dt_s},
      {"true_endpoint", {{"x", data.true_endpoint.x()}, {"y", data.true_endpoint.y()}}},
      {"reached_landmark", data.reached_landmark},
      {"reached_distance_m", data.reached_distance_m},
      {"landmarks", landmarks},
      {"disturbances", nullptr}};
  if (scenario.truth.disturbances.any()) {
    json disturbances = DisturbancesJson(scenario.truth.disturbances);
    disturbances["outlier_indices_x"] = data.outlier_indices_x;
    disturbances["outlier_indices_y"] = data.outlier_indices_y;
    truth["disturbances"] = disturbances;
  }
  return truth;
}

}  // namespace accelcal
