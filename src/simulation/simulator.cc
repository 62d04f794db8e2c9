#include "simulation/simulator.h"

#include <cmath>

#include "models/tilt_table.h"
#include "simulation/random.h"

namespace accelcal {

SimulationTruth CourseTableOneTruth() {
  SimulationTruth truth;
  truth.x.bias = 7.667e-2;
  truth.x.scale = -3.014e-2;
  truth.y.bias = -1.751e-2;
  truth.y.scale = 1.004e-2;
  truth.gravity_mps2 = kCourseGravityMps2;
  truth.noise_variance_x = 0.25;
  truth.noise_variance_y = 0.64;
  return truth;
}

CalibrationTest SimulateTiltTest(const TiltTestDesign& design, const SimulationTruth& truth,
                                 uint64_t seed, uint64_t stream) {
  RandomSource random(seed, stream);
  const double sigma_x = std::sqrt(truth.noise_variance_x);
  const double sigma_y = std::sqrt(truth.noise_variance_y);
  const int n = design.sample_count;
  CalibrationTest test;
  test.theta_rad.resize(n);
  test.measured_x.resize(n);
  test.measured_y.resize(n);
  for (int i = 0; i < n; ++i) {
    const double fraction = n > 1 ? static_cast<double>(i) / (n - 1) : 0.0;
    const double theta =
        design.theta_begin_rad + fraction * (design.theta_end_rad - design.theta_begin_rad);
    double force_x;
    double force_y;
    TiltTableSpecificForce(theta, truth.angle_offset_rad, truth.gravity_mps2, &force_x, &force_y);
    double along_x;
    double along_y;
    ProjectOnSensingAxes(force_x, force_y, truth.nonorthogonality_rad, &along_x, &along_y);
    const double u = DriftCoordinate(i, n);
    test.theta_rad[i] = theta;
    test.measured_x[i] = AxisOutput(along_x, truth.x, u, Phase::kCalibrationTest) +
                         sigma_x * random.StandardNormal();
    test.measured_y[i] = AxisOutput(along_y, truth.y, u, Phase::kCalibrationTest) +
                         sigma_y * random.StandardNormal();
  }
  return test;
}

VehicleRun SimulateVehicleRun(const std::vector<double>& timestamp_s,
                              const std::vector<double>& true_acceleration_x,
                              const std::vector<double>& true_acceleration_y,
                              const SimulationTruth& truth, uint64_t seed, uint64_t stream) {
  // A stream of its own, so that the run's noise is independent of the tilt test's
  // when both are simulated from one seed and stream.
  RandomSource random(seed, ~stream);
  const double sigma_x = std::sqrt(truth.noise_variance_x);
  const double sigma_y = std::sqrt(truth.noise_variance_y);
  VehicleRun run;
  run.timestamp_s = timestamp_s;
  run.measured_x.resize(timestamp_s.size());
  run.measured_y.resize(timestamp_s.size());
  for (size_t j = 0; j < timestamp_s.size(); ++j) {
    double along_x;
    double along_y;
    ProjectOnSensingAxes(true_acceleration_x[j], true_acceleration_y[j], truth.nonorthogonality_rad,
                         &along_x, &along_y);
    run.measured_x[j] =
        AxisOutput(along_x, truth.x, 0.0, Phase::kVehicleRun) + sigma_x * random.StandardNormal();
    run.measured_y[j] =
        AxisOutput(along_y, truth.y, 0.0, Phase::kVehicleRun) + sigma_y * random.StandardNormal();
  }
  return run;
}

}  // namespace accelcal
