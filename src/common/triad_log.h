#ifndef ACCELCAL_COMMON_TRIAD_LOG_H_
#define ACCELCAL_COMMON_TRIAD_LOG_H_

// A three-axis accelerometer log (and its gyroscope's, when logged): one time stamp and three
// outputs per sample, in whatever unit the sensor gives (raw ADC counts for imu_tk's Xsens
// log). The triad geometry's counterpart of CalibrationTest and VehicleRun (common/measurements.h).

#include <array>
#include <cstddef>
#include <vector>

namespace accelcal {

struct TriadLog {
  std::vector<double> timestamp_s;
  std::vector<std::array<double, 3>> output;  // x, y, z, in the sensor's unit
  // The gyroscope's outputs at the same time stamps, in its unit, when the log has them (a
  // log with gyroscope columns, or imu_tk's pair of files); else empty.
  std::vector<std::array<double, 3>> gyroscope;

  size_t size() const { return timestamp_s.size(); }
  bool has_gyroscope() const { return !gyroscope.empty(); }
  void Add(double t_s, double x, double y, double z) {
    timestamp_s.push_back(t_s);
    output.push_back({x, y, z});
  }
};

// One static pose of a triad: the mean and the sample variance (divided by N - 1) per axis of
// its N samples, in the log's unit. What the maximum-likelihood calibration fits
// (estimation/triad/triad_ml_calibration.h) and what the triad simulator produces.
struct TriadPoseMean {
  std::array<double, 3> mean{};
  std::array<double, 3> variance{};
  int sample_count = 0;
  double time_s = 0.0;      // mid-time of the pose (s, the log's clock)
  double duration_s = 0.0;  // last minus first sample's time stamp (s)
};

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_TRIAD_LOG_H_
