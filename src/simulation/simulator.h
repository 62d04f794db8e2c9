#ifndef ACCELCAL_SIMULATION_SIMULATOR_H_
#define ACCELCAL_SIMULATION_SIMULATOR_H_

// The tilt-table test and the vehicle run synthesised from the spec's model
// (models/tilt_table.h, models/sensor_model.h, the functions the estimators use) plus
// white Gaussian noise, with every effect of the catalogue (models/effects.h): the
// angle offset and the drift only in the test, the run bias shift only in the run, and
// noise whose true variance is the stated one times noise_variance_k. On top of the
// catalogue, the truth may hold disturbances that no effect represents
// (simulation/disturbances.h); all neutral, the output is what it would be without them.

#include <cstdint>
#include <vector>

#include "common/measurements.h"
#include "models/effects.h"
#include "simulation/disturbances.h"

namespace accelcal {

// The angles of a tilt test. kUniform: sample_count angles evenly spaced from
// theta_begin to theta_end, both included (the course: 20001 over [0, 2 pi]).
// kStaticPositions: sample_count samples split as evenly as possible among the
// positions, in order. kList: the angles as given.
struct TiltSchedule {
  enum class Kind { kUniform, kStaticPositions, kList };
  Kind kind = Kind::kUniform;
  int sample_count = 2001;
  double theta_begin_rad = 0.0;
  double theta_end_rad = 6.283185307179586;
  std::vector<double> positions_rad;  // kStaticPositions
  std::vector<double> angles_rad;     // kList
};

std::vector<double> TiltAngles(const TiltSchedule& schedule);

// The truth behind a simulated experiment.
struct SimulationTruth {
  ModelParameters<double> parameters;  // every effect neutral unless set
  double gravity_mps2 = 9.8;
  double stated_noise_variance_x = 0.25;  // (m/s^2)^2, as datos.txt would state it
  double stated_noise_variance_y = 0.64;
  Disturbances disturbances;  // outside the catalogue; every one neutral unless set

  double TrueNoiseVarianceX() const {
    return stated_noise_variance_x * parameters[Parameter::kNoiseVarianceX];
  }
  double TrueNoiseVarianceY() const {
    return stated_noise_variance_y * parameters[Parameter::kNoiseVarianceY];
  }
};

// The reference report's Table 1 as the sensor's errors, the course's stated noise
// variances and g; every other effect neutral.
SimulationTruth CourseTableOneTruth();

// Noise streams: (seed, stream) selects an independent sequence, so that a Monte Carlo
// trial's data depends on its index only, not on how trials are spread over threads.
// When given, outlier_indices_x and outlier_indices_y receive the samples the outlier
// disturbance hit on each axis, ascending.
CalibrationTest SimulateTiltTest(const TiltSchedule& schedule, const SimulationTruth& truth,
                                 uint64_t seed, uint64_t stream = 0,
                                 std::vector<int>* outlier_indices_x = nullptr,
                                 std::vector<int>* outlier_indices_y = nullptr);

// The vehicle run's outputs for the true accelerations (reference frame, m/s^2) at the
// given times. Its noise comes from a stream of its own, independent of the tilt test's
// for the same (seed, stream).
VehicleRun SimulateVehicleRun(const std::vector<double>& timestamp_s,
                              const std::vector<double>& true_acceleration_x,
                              const std::vector<double>& true_acceleration_y,
                              const SimulationTruth& truth, uint64_t seed, uint64_t stream = 0);

}  // namespace accelcal

#endif  // ACCELCAL_SIMULATION_SIMULATOR_H_
