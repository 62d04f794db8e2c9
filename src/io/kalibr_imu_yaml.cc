#include "io/kalibr_imu_yaml.h"

#include <algorithm>
#include <cmath>

#include "common/format.h"
#include "common/line_text.h"

namespace accelcal {
namespace {

constexpr const char* kAxes[3] = {"x", "y", "z"};

// A positive finite number at json[key], or a message naming the key.
Status PositiveNumber(const nlohmann::json& json, const std::string& where, const char* key,
                      double* value) {
  if (!json.is_object() || !json.contains(key) || !json.at(key).is_number() ||
      !std::isfinite(json.at(key).get<double>()) || !(json.at(key).get<double>() > 0.0)) {
    return Status::Error(where + key + " must be a positive number");
  }
  *value = json.at(key).get<double>();
  return Status::Ok();
}

// The largest random walk an Allan curve allows: min over its points of sqrt(3/tau) adev_high.
Status RandomWalkBound(const nlohmann::json& axis, const std::string& where, double* bound,
                       double* at_tau_s) {
  const nlohmann::json& points = axis.contains("points") ? axis.at("points") : nlohmann::json();
  if (!points.is_array() || points.empty())
    return Status::Error(where + "points must be a non-empty list");
  *bound = INFINITY;
  for (size_t j = 0; j < points.size(); ++j) {
    double tau_s = 0.0, adev_high = 0.0;
    const std::string point = where + "points/" + std::to_string(j) + "/";
    ACCELCAL_RETURN_IF_ERROR(PositiveNumber(points[j], point, "tau_s", &tau_s));
    ACCELCAL_RETURN_IF_ERROR(PositiveNumber(points[j], point, "adev_high", &adev_high));
    const double k = std::sqrt(3.0 / tau_s) * adev_high;
    if (k < *bound) {
      *bound = k;
      *at_tau_s = tau_s;
    }
  }
  return Status::Ok();
}

}  // namespace

Status KalibrNoiseFromAllan(const nlohmann::json& allan, const std::string& allan_path,
                            const std::string& output_unit, const Eigen::Matrix3d& matrix,
                            const std::string& sensor, KalibrSensorNoise* noise) {
  *noise = KalibrSensorNoise();
  const std::string file = allan_path + ": ";
  if (!allan.is_object() || !allan.contains("problem") || allan.at("problem") != "allan") {
    return Status::Error(file + "not allan's JSON (its \"problem\" is not \"allan\"): give the " +
                         sensor + "'s Allan fit, allan --log=... --json=FILE");
  }
  if (!allan.contains("output_unit") || !allan.at("output_unit").is_string() ||
      allan.at("output_unit").get<std::string>() != output_unit) {
    return Status::Error(
        file + "output_unit is " +
        (allan.contains("output_unit") ? allan.at("output_unit").dump() : std::string("missing")) +
        ", but the calibration's " + sensor + " maps output in \"" + output_unit +
        "\": run allan on the " + sensor + "'s log in that unit (its --unit)");
  }
  double gain = 0.0, sample_period_s = 0.0;
  ACCELCAL_RETURN_IF_ERROR(PositiveNumber(allan, file, "gain", &gain));
  ACCELCAL_RETURN_IF_ERROR(PositiveNumber(allan, file, "sample_period_s", &sample_period_s));
  noise->update_rate_hz = 1.0 / sample_period_s;
  if (!allan.contains("axes") || !allan.at("axes").is_object())
    return Status::Error(file + "axes must be an object with x, y and z");
  // Per axis of the output, in its unit: the white noise N_k and the random walk K_k.
  Eigen::Vector3d white, walk;
  std::string resolved_axes, bounded_axes;  // "x, y" ...
  for (int k = 0; k < 3; ++k) {
    const std::string where = file + "axes/" + kAxes[k] + "/";
    if (!allan.at("axes").contains(kAxes[k]))
      return Status::Error(file + "axes/" + kAxes[k] + " is missing");
    const nlohmann::json& axis = allan.at("axes").at(kAxes[k]);
    const nlohmann::json& n =
        axis.contains("white_noise") ? axis.at("white_noise") : nlohmann::json();
    const nlohmann::json& rw =
        axis.contains("random_walk") ? axis.at("random_walk") : nlohmann::json();
    if (!n.is_object() || !n.contains("resolved") || n.at("resolved") != true) {
      return Status::Error(where +
                           "white_noise is not resolved: a curve without white noise is not a "
                           "static IMU log's; Kalibr needs a noise density (check the log and "
                           "allan's --segment)");
    }
    double n_value = 0.0;
    ACCELCAL_RETURN_IF_ERROR(PositiveNumber(n, where + "white_noise/", "value", &n_value));
    white[k] = n_value / gain;
    if (rw.is_object() && rw.contains("resolved") && rw.at("resolved") == true) {
      double k_value = 0.0;
      ACCELCAL_RETURN_IF_ERROR(PositiveNumber(rw, where + "random_walk/", "value", &k_value));
      walk[k] = k_value / gain;
      noise->notes.push_back(
          StringPrintf("%s %s: random walk K resolved by the Allan fit", sensor.c_str(), kAxes[k]));
    } else {
      double bound = 0.0, at_tau_s = 0.0;
      ACCELCAL_RETURN_IF_ERROR(RandomWalkBound(axis, where, &bound, &at_tau_s));
      walk[k] = bound / gain;
      bounded_axes +=
          StringPrintf("%s%s (tau = %.6g s)", bounded_axes.empty() ? "" : ", ", kAxes[k], at_tau_s);
    }
  }
  if (!resolved_axes.empty()) {
    noise->notes.push_back(sensor + ": random walk K resolved by the Allan fit on " +
                           resolved_axes);
  }
  if (!bounded_axes.empty()) {
    noise->notes.push_back(sensor + ": random walk K not resolved by the Allan fit on " +
                           bounded_axes +
                           ": the largest the curve allows, min over tau of sqrt(3/tau) "
                           "adev_high(tau) (docs/calibration.md, Exports)");
  }
  // The corrected axes' terms, x = M u: sqrt(sum_k M_ik^2 term_k^2); Kalibr takes one number.
  const Eigen::Matrix3d squared = matrix.cwiseAbs2();
  const Eigen::Vector3d white_out = (squared * white.cwiseAbs2()).cwiseSqrt();
  const Eigen::Vector3d walk_out = (squared * walk.cwiseAbs2()).cwiseSqrt();
  noise->noise_density = white_out.maxCoeff();
  noise->random_walk = walk_out.maxCoeff();
  noise->notes.push_back(StringPrintf(
      "%s: corrected axes' noise density (%.6g, %.6g, %.6g), random walk (%.6g, %.6g, %.6g); "
      "the largest of each written",
      sensor.c_str(), white_out[0], white_out[1], white_out[2], walk_out[0], walk_out[1],
      walk_out[2]));
  if (!(noise->noise_density > 0.0) || !(noise->random_walk > 0.0) ||
      !std::isfinite(noise->noise_density) || !std::isfinite(noise->random_walk)) {
    return Status::Error(file + "the " + sensor +
                         "'s terms are not positive and finite after the calibration: Kalibr "
                         "refuses a term that is not positive");
  }
  return Status::Ok();
}

std::string KalibrImuYamlText(const KalibrImuConfig& config,
                              const std::vector<std::string>& header_comments) {
  std::string text;
  // A comment is one line whatever it quotes (a path may hold a line break, which YAML would
  // read as the end of the comment and the start of a key): common/line_text.h's rule.
  for (const std::string& line : header_comments) text += "# " + EscapeForLine(line) + "\n";
  text += StringPrintf("accelerometer_noise_density: %.17g  # m/s^2/sqrt(Hz)\n",
                       config.accelerometer.noise_density);
  text += StringPrintf("accelerometer_random_walk: %.17g  # m/s^3/sqrt(Hz)\n",
                       config.accelerometer.random_walk);
  text += StringPrintf("gyroscope_noise_density: %.17g  # rad/s/sqrt(Hz)\n",
                       config.gyroscope.noise_density);
  text += StringPrintf("gyroscope_random_walk: %.17g  # rad/s^2/sqrt(Hz)\n",
                       config.gyroscope.random_walk);
  text += StringPrintf("update_rate: %.17g  # Hz\n", config.update_rate_hz);
  // A topic is a ROS name ([A-Za-z0-9_/~]), which YAML reads as a plain string.
  text += "rostopic: " + config.rostopic + "\n";
  for (const KalibrSensorNoise* sensor : {&config.accelerometer, &config.gyroscope})
    for (const std::string& note : sensor->notes) text += "# " + EscapeForLine(note) + "\n";
  return text;
}

}  // namespace accelcal
