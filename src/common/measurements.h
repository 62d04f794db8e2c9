#ifndef ACCELCAL_COMMON_MEASUREMENTS_H_
#define ACCELCAL_COMMON_MEASUREMENTS_H_

// Plain containers for what the instruments recorded, in SI units, with the names of
// ../shared/spec/error-model.md. They carry no behaviour: io/ fills them, simulation/
// synthesises them, estimation/ reads them.

#include <string>
#include <vector>

namespace accelcal {

// The tilt-table test: the reported table angle and both sensors' outputs per sample.
struct CalibrationTest {
  std::vector<double> theta_rad;   // reported angle theta_i, rad
  std::vector<double> measured_x;  // m_x, m/s^2
  std::vector<double> measured_y;  // m_y, m/s^2

  int size() const { return static_cast<int>(theta_rad.size()); }

  // Appends `more`'s samples after these (a test read or simulated in batches).
  void Append(const CalibrationTest& more) {
    theta_rad.insert(theta_rad.end(), more.theta_rad.begin(), more.theta_rad.end());
    measured_x.insert(measured_x.end(), more.measured_x.begin(), more.measured_x.end());
    measured_y.insert(measured_y.end(), more.measured_y.begin(), more.measured_y.end());
  }
};

// The vehicle run: uniformly sampled outputs of both sensors.
struct VehicleRun {
  std::vector<double> timestamp_s;  // t_j, s
  std::vector<double> measured_x;   // m/s^2
  std::vector<double> measured_y;   // m/s^2

  int size() const { return static_cast<int>(timestamp_s.size()); }

  // The uniform sample interval dt = (t_last - t_first) / (n - 1), s; 0 with fewer than two
  // samples. The one place dt is computed (io/ checks on reading that the steps are uniform).
  double SampleInterval() const {
    return size() < 2 ? 0.0 : (timestamp_s.back() - timestamp_s.front()) / (size() - 1);
  }
};

// A candidate place where the run may have ended.
struct Landmark {
  std::string name;
  double x_m = 0.0;
  double y_m = 0.0;
};

// Initial conditions and stated noise of the run (datos.txt, or scenario.json in the
// CSV layout).
struct RunConditions {
  double initial_position_x_m = 0.0;
  double initial_position_y_m = 0.0;
  double initial_velocity_x_mps = 0.0;
  double initial_velocity_y_mps = 0.0;
  double noise_variance_x = 0.0;  // stated sigma_x^2, (m/s^2)^2
  double noise_variance_y = 0.0;  // stated sigma_y^2, (m/s^2)^2
  bool has_gravity = false;       // scenario.json may state g; datos.txt never does
  double gravity_mps2 = 9.8;
};

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_MEASUREMENTS_H_
