#ifndef ACCELCAL_IO_CALIBRATION_FILE_H_
#define ACCELCAL_IO_CALIBRATION_FILE_H_

// The calibration file: what `calibrate` writes and `apply`, `trajectory` (--calibration)
// read. One versioned JSON format, stated in docs/calibration.md, that a reader needs no
// part of this project to use (Python's json module reads it):
//
//   {"format": "accelcal-calibration", "format_version": 1,
//    "model": {"geometry": "two_axis", "axes": ["x", "y"], "effects": ["bias", "scale"],
//              "measurement": "m_k = (1 + scale_k) a_k + bias_k + noise_k", ...},
//    "gravity_mps2": 9.8,
//    "parameter_order": ["bias_x", "scale_x", "bias_y", "scale_y"],
//    "parameters": {"bias_x": 0.0767, ...}, "units": {"bias_x": "m/s^2", ...},
//    "stddev": {...}, "covariance": [[...], ...]   (parameter_order's order),
//    "noise_variance": {"x": 0.25, "y": 0.64, "unit": "(m/s^2)^2", "from": "datos.txt"},
//    "fit": {...}, "created_utc": "...", and the provenance keys (io/provenance.h)}
//
// The reader refuses, in one line naming the file and the key, a file of another format or
// a newer version, a parameter missing or unknown, a unit other than the model's, a
// covariance that is not symmetric positive semi-definite with positive variances, and any
// non-finite number: a calibration applied with a wrong unit or a broken covariance would
// give confident wrong answers downstream.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/status.h"
#include "io/provenance.h"

namespace accelcal {

constexpr char kCalibrationFormat[] = "accelcal-calibration";
constexpr int kCalibrationFormatVersion = 1;

// A calibration: parameters by name with their joint covariance, under a sensor geometry.
struct CalibrationRecord {
  std::string geometry = "two_axis";
  std::vector<std::string> parameter_order;  // spec names
  Eigen::VectorXd values;
  Eigen::MatrixXd covariance;  // parameter_order's order
  double gravity_mps2 = 9.8;
  // Per axis ("x", "y"), (m/s^2)^2, and where it came from: "--noise_variance",
  // a conditions file's name, or "estimated from the residuals".
  std::vector<double> noise_variance;
  std::string noise_variance_from;
  nlohmann::json fit = nlohmann::json::object();  // samples, chi-square, verdict
  std::string created_utc;                        // ISO 8601, set by the writer
  DataSource source;  // the tilt test it was computed from (written, not read back)
  // Read back only: the writer's version and command line.
  std::string written_by_version;
  std::string written_by_command_line;

  // The index of `name` in parameter_order, or -1.
  int IndexOf(const std::string& name) const;
};

// The geometry's parameters, units and axes (only "two_axis" today: bias_x, scale_x,
// bias_y, scale_y from the catalogue, models/effects.h).
struct GeometryInfo {
  std::vector<std::string> parameters;
  std::vector<std::string> units;
  std::vector<std::string> axes;
  std::vector<std::string> effects;
  const char* measurement;  // the model, in the spec's words
  const char* correction;   // its inverse, as apply uses it
};
Status GeometryOf(const std::string& geometry, GeometryInfo* info);

// The file's JSON. The current UTC time is written as created_utc.
nlohmann::json CalibrationJson(const CalibrationRecord& record);

// Parses and checks a calibration file's text; `path` names it in messages.
Status ParseCalibration(const std::string& text, const std::string& path,
                        CalibrationRecord* record);
Status ReadCalibrationFile(const std::string& path, CalibrationRecord* record);

// A two-axis calibration's parameters and covariance in parameter_order's order (bias_x,
// scale_x, bias_y, scale_y: the baseline's, estimation/baseline_parameters.h); fails, naming
// `path`, for another geometry.
Status TwoAxisBaseline(const CalibrationRecord& record, const std::string& path,
                       Eigen::Vector4d* parameters, Eigen::Matrix4d* covariance);

}  // namespace accelcal

#endif  // ACCELCAL_IO_CALIBRATION_FILE_H_
