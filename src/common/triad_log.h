#ifndef ACCELCAL_COMMON_TRIAD_LOG_H_
#define ACCELCAL_COMMON_TRIAD_LOG_H_

// A three-axis accelerometer log: one time stamp and three outputs per sample, in whatever
// unit the sensor gives (raw ADC counts for imu_tk's Xsens log). The triad geometry's
// counterpart of CalibrationTest and VehicleRun (common/measurements.h).

#include <array>
#include <cstddef>
#include <vector>

namespace accelcal {

struct TriadLog {
  std::vector<double> timestamp_s;
  std::vector<std::array<double, 3>> output;  // x, y, z, in the sensor's unit

  size_t size() const { return timestamp_s.size(); }
  void Add(double t_s, double x, double y, double z) {
    timestamp_s.push_back(t_s);
    output.push_back({x, y, z});
  }
};

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_TRIAD_LOG_H_
