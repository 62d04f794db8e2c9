#include "simulation/simulator.h"

#include <cmath>

#include "models/sensor_model.h"
#include "models/tilt_table.h"
#include "simulation/random.h"

namespace accelcal {

std::vector<double> TiltAngles(const TiltSchedule& schedule) {
  std::vector<double> angles;
  switch (schedule.kind) {
    case TiltSchedule::Kind::kUniform: {
      const int n = schedule.sample_count;
      angles.resize(n > 0 ? n : 0);
      for (int i = 0; i < n; ++i) {
        const double fraction = n > 1 ? static_cast<double>(i) / (n - 1) : 0.0;
        angles[i] = schedule.theta_begin_rad +
                    fraction * (schedule.theta_end_rad - schedule.theta_begin_rad);
      }
      break;
    }
    case TiltSchedule::Kind::kStaticPositions: {
      const int positions = static_cast<int>(schedule.positions_rad.size());
      for (int p = 0; p < positions; ++p) {
        // Position p gets samples [p N / P, (p + 1) N / P): sizes differ by at most one.
        const int begin =
            static_cast<int>(static_cast<long long>(p) * schedule.sample_count / positions);
        const int end =
            static_cast<int>(static_cast<long long>(p + 1) * schedule.sample_count / positions);
        angles.insert(angles.end(), end - begin, schedule.positions_rad[p]);
      }
      break;
    }
    case TiltSchedule::Kind::kList:
      angles = schedule.angles_rad;
      break;
  }
  return angles;
}

SimulationTruth CourseTableOneTruth() {
  SimulationTruth truth;
  truth.parameters[Parameter::kBiasX] = 7.667e-2;
  truth.parameters[Parameter::kScaleX] = -3.014e-2;
  truth.parameters[Parameter::kBiasY] = -1.751e-2;
  truth.parameters[Parameter::kScaleY] = 1.004e-2;
  truth.gravity_mps2 = kCourseGravityMps2;
  truth.stated_noise_variance_x = 0.25;
  truth.stated_noise_variance_y = 0.64;
  return truth;
}

CalibrationTest SimulateTiltTest(const TiltSchedule& schedule, const SimulationTruth& truth,
                                 uint64_t seed, uint64_t stream,
                                 std::vector<int>* outlier_indices_x,
                                 std::vector<int>* outlier_indices_y) {
  RandomSource random(seed, 2 * stream);
  const ModelParameters<double>& p = truth.parameters;
  const double sigma_x = std::sqrt(truth.TrueNoiseVarianceX());
  const double sigma_y = std::sqrt(truth.TrueNoiseVarianceY());
  CalibrationTest test;
  test.theta_rad = TiltAngles(schedule);
  const int n = test.size();
  test.measured_x.resize(n);
  test.measured_y.resize(n);
  SampleDisturber disturber(truth.disturbances, Phase::kCalibrationTest, n, sigma_x, sigma_y, seed,
                            2 * stream, test.theta_rad);
  for (int i = 0; i < n; ++i) {
    PredictCalibrationOutputs(test.theta_rad[i], DriftCoordinate(i, n), truth.gravity_mps2, p,
                              &test.measured_x[i], &test.measured_y[i]);
    double along_x = 0.0;
    double along_y = 0.0;
    if (disturber.needs_forces()) {
      CalibrationForcesAlongAxes(test.theta_rad[i], truth.gravity_mps2, p, &along_x, &along_y);
    }
    // x's draw first, as always: a seed's data must not change.
    const double normal_x = random.StandardNormal();
    const double normal_y = random.StandardNormal();
    disturber.Apply(i, test.theta_rad[i], along_x, along_y, normal_x, normal_y, &test.measured_x[i],
                    &test.measured_y[i]);
  }
  if (outlier_indices_x != nullptr) *outlier_indices_x = disturber.outlier_indices_x();
  if (outlier_indices_y != nullptr) *outlier_indices_y = disturber.outlier_indices_y();
  return test;
}

VehicleRun SimulateVehicleRun(const std::vector<double>& timestamp_s,
                              const std::vector<double>& true_acceleration_x,
                              const std::vector<double>& true_acceleration_y,
                              const SimulationTruth& truth, uint64_t seed, uint64_t stream) {
  RandomSource random(seed, 2 * stream + 1);
  const ModelParameters<double>& p = truth.parameters;
  const double sigma_x = std::sqrt(truth.TrueNoiseVarianceX());
  const double sigma_y = std::sqrt(truth.TrueNoiseVarianceY());
  VehicleRun run;
  run.timestamp_s = timestamp_s;
  run.measured_x.resize(timestamp_s.size());
  run.measured_y.resize(timestamp_s.size());
  SampleDisturber disturber(truth.disturbances, Phase::kVehicleRun,
                            static_cast<int>(timestamp_s.size()), sigma_x, sigma_y, seed,
                            2 * stream + 1);
  for (size_t j = 0; j < timestamp_s.size(); ++j) {
    PredictRunOutputs(true_acceleration_x[j], true_acceleration_y[j], p, &run.measured_x[j],
                      &run.measured_y[j]);
    double along_x = 0.0;
    double along_y = 0.0;
    if (disturber.needs_forces()) {
      ProjectOnSensingAxes(true_acceleration_x[j], true_acceleration_y[j], p, Phase::kVehicleRun,
                           &along_x, &along_y);
    }
    const double normal_x = random.StandardNormal();
    const double normal_y = random.StandardNormal();
    disturber.Apply(static_cast<int>(j), 0.0, along_x, along_y, normal_x, normal_y,
                    &run.measured_x[j], &run.measured_y[j]);
  }
  return run;
}

}  // namespace accelcal
