#ifndef ACCELCAL_SIMULATION_SIMULATOR_H_
#define ACCELCAL_SIMULATION_SIMULATOR_H_

// The tilt-table test and the vehicle run synthesised from the spec's model (models/tilt_table.h
// and models/sensor_model.h, the functions the estimators use) plus white Gaussian noise. It
// already honours every term of the sensor model; the simulator issue grows the design (schedules,
// static positions) and the vehicle run around it.

#include <cstdint>
#include <vector>

#include "common/measurements.h"
#include "models/sensor_model.h"

namespace accelcal {

// Angles uniformly spaced from theta_begin to theta_end, both included (the course's
// test: 20001 samples over [0, 2 pi]).
struct TiltTestDesign {
  int sample_count = 2001;
  double theta_begin_rad = 0.0;
  double theta_end_rad = 6.283185307179586;
};

// The truth behind a simulated experiment (tilt test and vehicle run).
struct SimulationTruth {
  AxisErrors<double> x;
  AxisErrors<double> y;
  double nonorthogonality_rad = 0.0;
  double angle_offset_rad = 0.0;
  double gravity_mps2 = 9.8;
  double noise_variance_x = 0.25;  // true sigma_x^2, (m/s^2)^2
  double noise_variance_y = 0.64;  // true sigma_y^2, (m/s^2)^2
};

// The truth of the embedded default: the reference report's Table 1 as the sensor's
// errors, the course's stated noise variances and g.
SimulationTruth CourseTableOneTruth();

CalibrationTest SimulateTiltTest(const TiltTestDesign& design, const SimulationTruth& truth,
                                 uint64_t seed, uint64_t stream = 0);

// The vehicle run's outputs for the true accelerations (reference frame, m/s^2) at the
// given times: the spec's forward model in the run phase (no angle offset, no drift,
// the run bias shift) plus white noise of the true variances.
VehicleRun SimulateVehicleRun(const std::vector<double>& timestamp_s,
                              const std::vector<double>& true_acceleration_x,
                              const std::vector<double>& true_acceleration_y,
                              const SimulationTruth& truth, uint64_t seed, uint64_t stream = 0);

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_SIMULATOR_H_
