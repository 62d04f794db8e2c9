#ifndef ACCELCAL_SIMULATION_SCENARIO_H_
#define ACCELCAL_SIMULATION_SCENARIO_H_

// A simulated experiment: the truth, the tilt table's schedule, the run's profile and the
// landmarks, and the simulation of one data set from it. Scenarios are written as
// data/scenarios/*.json and --set assignments, read by io/scenario_json.h (which states the
// format); omitted truths and disturbances are neutral (no effect).

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/measurements.h"
#include "common/status.h"
#include "simulation/simulator.h"

namespace accelcal {

struct AccelerationSegment {
  double duration_s = 0.0;
  double acceleration_x = 0.0;  // m/s^2
  double acceleration_y = 0.0;
};

struct RunProfile {
  double dt_s = 0.01;
  double duration_s = 60.0;
  std::vector<AccelerationSegment> segments;
  double smoothing_s = 0.0;
  // From a CSV instead of segments (filled when the scenario names one).
  std::vector<double> csv_acceleration_x;
  std::vector<double> csv_acceleration_y;
};

struct LandmarkSpec {
  std::vector<Landmark> listed;
  bool decoys = false;  // the true endpoint plus decoy_count decoys
  int decoy_count = 3;
  double decoy_min_distance_m = 100.0;
};

struct Scenario {
  std::string name;
  std::string description;
  SimulationTruth truth;  // g, stated variances and every parameter
  double initial_position_x_m = 0.0;
  double initial_position_y_m = 0.0;
  double initial_velocity_x_mps = 0.0;
  double initial_velocity_y_mps = 0.0;
  TiltSchedule tilt;
  RunProfile run;
  LandmarkSpec landmarks;
};

// One simulated experiment with its truth.
struct SimulatedData {
  CalibrationTest test;
  VehicleRun run;
  std::vector<Landmark> landmarks;
  RunConditions conditions;  // what datos.txt states: p0, v0, stated variances
  std::vector<double> true_acceleration_x;
  std::vector<double> true_acceleration_y;
  Eigen::Vector2d true_endpoint = Eigen::Vector2d::Zero();
  std::string reached_landmark;     // the landmark nearest the true endpoint
  double reached_distance_m = 0.0;  // its distance from the true endpoint
  // The tilt-test samples the outlier disturbance hit, per axis, ascending.
  std::vector<int> outlier_indices_x;
  std::vector<int> outlier_indices_y;
};

// The true accelerations of the run (segments smoothed, or the CSV) at t_j = j dt.
void TrueRunAcceleration(const RunProfile& profile, std::vector<double>* timestamp_s,
                         std::vector<double>* acceleration_x, std::vector<double>* acceleration_y);

// Deterministic for (seed, trial) on any machine.
SimulatedData SimulateScenario(const Scenario& scenario, uint64_t seed, uint64_t trial = 0);

// Every true value and setting, named as in the spec (for truth.json). When a disturbance
// is set, "disturbances" holds every one by its --set name and the outlier samples,
// "outlier_indices_x" and "outlier_indices_y".
nlohmann::json TruthJson(const Scenario& scenario, const SimulatedData& data, uint64_t seed);

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_SCENARIO_H_
