#ifndef ACCELCAL_IO_KALIBR_IMU_YAML_H_
#define ACCELCAL_IO_KALIBR_IMU_YAML_H_

// Kalibr's IMU configuration, imu.yaml (its kalibr_common/ConfigReader.py, ImuParameters; the
// wiki's "IMU Noise Model" and "YAML formats"): the noise of the IMU whose sensor_msgs/Imu
// messages Kalibr's camera-IMU calibration reads,
//
//   accelerometer_noise_density: m/s^2/sqrt(Hz)   white noise, continuous time (sigma_a)
//   accelerometer_random_walk:   m/s^3/sqrt(Hz)   the bias's Brownian motion (sigma_ba)
//   gyroscope_noise_density:     rad/s/sqrt(Hz)   (sigma_g)
//   gyroscope_random_walk:       rad/s^2/sqrt(Hz) (sigma_bg)
//   update_rate:                 Hz               (Kalibr: sigma_discrete = sigma / sqrt(1/rate))
//   rostopic:                    the topic of the messages
//
// one number per sensor for its three axes, every one positive (ConfigReader refuses 0). It
// carries no intrinsics: Kalibr's reader reads nothing else from this file, and its
// scale-misalignment IMU models start their matrices from the identity and estimate them, so the
// messages must already be corrected (apply's output).
//
// Each term comes from an Allan fit of the sensor's static log (allan --json, docs/noise.md) in
// the calibration's output unit, carried into the corrected output through the calibration's
// matrix M = T K (models/triad.h, models/gyroscope.h) (docs/calibration.md, "Exports"):
//   - noise density: the white-noise term N_k (Allan deviation N/sqrt(tau)), the corrected
//     axis i's sqrt(sum_k M_ik^2 N_k^2), the largest of the three axes;
//   - random walk: the rate-random-walk term K_k (Allan deviation K sqrt(tau/3)) when the fit
//     resolves it; when it does not (its interval reaches 0, as a short rest dominated by bias
//     instability gives), the largest random walk the curve allows: the K whose line
//     K sqrt(tau/3) touches the curve's upper confidence limit, min over tau of
//     sqrt(3/tau) adev_high(tau); carried through M and maximised over axes as N is.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/status.h"

namespace accelcal {

// One sensor's two terms in its corrected unit (m/s^2 or rad/s), and the Allan log's rate.
struct KalibrSensorNoise {
  double noise_density = 0.0;  // unit/sqrt(Hz)
  double random_walk = 0.0;    // unit/s/sqrt(Hz) = unit sqrt(Hz)
  double update_rate_hz = 0.0;
  std::vector<std::string> notes;  // how each term was taken, for the file's comments
};

// The terms of one sensor from `allan` (allan's JSON, read from `allan_path`, named in
// messages), whose log must be in `output_unit` (the calibration's: "count", "m/s^2", "g",
// "rad/s" or "deg/s"), through `matrix` (corrected unit per output unit). `sensor` names it in
// notes and messages ("accelerometer"). Fails, naming the file and the key, for a JSON that is
// not allan's, a log in another unit, or a term neither resolved nor bounded above 0.
Status KalibrNoiseFromAllan(const nlohmann::json& allan, const std::string& allan_path,
                            const std::string& output_unit, const Eigen::Matrix3d& matrix,
                            const std::string& sensor, KalibrSensorNoise* noise);

struct KalibrImuConfig {
  KalibrSensorNoise accelerometer;  // m/s^2
  KalibrSensorNoise gyroscope;      // rad/s
  double update_rate_hz = 0.0;
  std::string rostopic = "/imu0";
};

// imu.yaml's text: `header_comments` as '#' lines, the six keys with their units in trailing
// comments (numbers at full precision), then each sensor's notes as '#' lines.
std::string KalibrImuYamlText(const KalibrImuConfig& config,
                              const std::vector<std::string>& header_comments);

}  // namespace accelcal

#endif  // ACCELCAL_IO_KALIBR_IMU_YAML_H_
