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
//    "fit": {...}, "poorly_determined": [...] or null, "created_utc": "...", and the
//    provenance keys (io/provenance.h)}
//
//
// A triad's file may carry its gyroscope's calibration too, in an object of its own (null when
// there is none; a file without the key, written before it, reads as none):
//
//   "gyroscope": {"model": {"measurement": "w = T K (u - b), ...", "conventions": ...},
//                 "output_unit": "count", "parameter_order": [the 9 of models/gyroscope.h's
//                 block, then "gyroscope_offset_x", "_y", "_z"], "parameters", "units",
//                 "stddev", "covariance" (12x12), "fit": {...}}
//
// Version 1 still: the section adds a key and changes none, and a version-1 reader that does
// not know it ignores it (ParseCalibration reads only the keys it knows).
//
// The reader refuses, in one line naming the file and the key, a file of another format or
// a newer version, a parameter missing or unknown, a unit other than the model's, a
// covariance that is not symmetric positive semi-definite with positive variances, a stddev
// that is not the square root of the covariance's diagonal (relative 1e-6; optional in the
// accelerometer's part, which hand-written files of version 1 omit, required in the
// gyroscope's), and any non-finite number, and a `poorly_determined` that is not a list of
// objects each naming a parameter of the file: a calibration applied with a wrong unit or a
// broken covariance would give confident wrong answers downstream. The gyroscope's section is
// checked alike. Arrays and objects nested deeper than kMaxJsonDepth are refused before
// anything is built from them (io/json_file.h). The model's text, when given (model.measurement,
// correction, axes, effects; the gyroscope's measurement from its equation "w = T K (u - b)"),
// must be what this version writes for the geometry: a file of another model is refused.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/status.h"
#include "io/provenance.h"
#include "models/gyroscope.h"
#include "models/gyroscope_units.h"
#include "models/triad.h"
#include "models/triad_units.h"

namespace accelcal {

constexpr char kCalibrationFormat[] = "accelcal-calibration";
constexpr int kCalibrationFormatVersion = 1;

// A triad's gyroscope calibration: w = T K (u - b) (models/gyroscope.h), the block's 9
// parameters then the offsets, with their joint covariance. Build it with
// MakeGyroscopeCalibrationSection.
struct GyroscopeCalibrationSection {
  // The unit of the gyroscope's log: "count", "rad/s" or "deg/s" (models/gyroscope_units.h);
  // it sets the gains' and offsets' units.
  std::string output_unit = "count";
  std::vector<std::string> parameter_order;       // GyroscopeCalibrationParameterName(0..11)
  Eigen::VectorXd values;                         // parameter_order's order
  Eigen::MatrixXd covariance;                     // 12x12, parameter_order's order
  nlohmann::json fit = nlohmann::json::object();  // the estimator's own summary, free form
  // The unknowns the session determines too loosely to vouch for
  // (estimation/gyroscope/gyroscope_determination.h), each as CalibrationRecord::
  // poorly_determined's entries; null when not assessed (a file written before the key existed,
  // which the reader accepts), an empty array when none.
  nlohmann::json poorly_determined = nullptr;
};

// The section of a gyroscope's calibration: `parameters` (the block), `offset` (in `unit`) and
// their 12x12 `covariance` (the block's 9 in order, then the offset's x, y, z); `fit` is left
// empty for the caller. Fails, in one line naming the key, for what the file's reader would
// refuse (a covariance of another size, not finite, not symmetric positive semi-definite with
// positive variances; gains that are not positive or contradict `unit`), so that a file
// written is a file apply reads.
Status MakeGyroscopeCalibrationSection(const GyroscopeParameters& parameters,
                                       const GyroscopeOffset& offset,
                                       const Eigen::MatrixXd& covariance, GyroscopeOutputUnit unit,
                                       GyroscopeCalibrationSection* section);

// The section's block, offset, covariance and unit, for apply.
Status GyroscopeCalibration(const GyroscopeCalibrationSection& section,
                            GyroscopeParameters* parameters, GyroscopeOffset* offset,
                            Eigen::MatrixXd* covariance, GyroscopeOutputUnit* unit);

// A calibration: parameters by name with their joint covariance, under a sensor geometry.
struct CalibrationRecord {
  std::string geometry = "two_axis";
  // The unit of the sensor's output the parameters map from: "m/s^2" for two_axis; for a
  // triad "count", "m/s^2" or "g" (models/triad_units.h), which sets its parameters' units.
  std::string output_unit = "m/s^2";
  std::vector<std::string> parameter_order;  // spec names
  Eigen::VectorXd values;
  Eigen::MatrixXd covariance;  // parameter_order's order
  double gravity_mps2 = 9.8;
  // Per axis (the geometry's axes), in output_unit squared, and where it came from:
  // "--noise_variance", a conditions file's name, "estimated from the residuals" or, for a
  // triad, "pooled within-pose variances".
  std::vector<double> noise_variance;
  std::string noise_variance_from;
  nlohmann::json fit = nlohmann::json::object();  // samples, chi-square, verdict
  // The parameters the data determine too loosely to vouch for (a triad's:
  // estimation/triad/triad_determination.h), each {parameter, reason, sigma, threshold,
  // correlated_with, suggestion}; null when not assessed (a two-axis calibration, or a file
  // written before the key existed, which the reader accepts), an empty array when none.
  nlohmann::json poorly_determined = nullptr;
  // A triad's gyroscope, when calibrated with it (written as "gyroscope": null otherwise).
  bool has_gyroscope = false;
  GyroscopeCalibrationSection gyroscope;
  std::string created_utc;  // ISO 8601, set by the writer
  DataSource source;        // the tilt test it was computed from (written, not read back)
  // Read back only: the writer's version and command line.
  std::string written_by_version;
  std::string written_by_command_line;

  // The index of `name` in parameter_order, or -1.
  int IndexOf(const std::string& name) const;
};

// A geometry's parameters, units and axes, for a given output unit:
//   two_axis (output m/s^2): bias_x, scale_x, bias_y, scale_y from the catalogue,
//     models/effects.h;
//   triad (output count, m/s^2 or g): misalignment_yz, _zy, _zx, gain_x.., offset_x.. of
//     models/triad.h, their units from models/triad_units.h.
struct GeometryInfo {
  std::vector<std::string> parameters;
  std::vector<std::string> units;
  std::vector<std::string> axes;
  std::vector<std::string> effects;
  const char* measurement;  // the model, in the spec's words
  const char* correction;   // its inverse, as apply uses it
  const char* conventions;  // what the symbols are, in words
};
Status GeometryOf(const std::string& geometry, const std::string& output_unit, GeometryInfo* info);

// The file's JSON. The current UTC time is written as created_utc.
nlohmann::json CalibrationJson(const CalibrationRecord& record);

// Parses and checks a calibration file's text; `path` names it in messages.
Status ParseCalibration(const std::string& text, const std::string& path,
                        CalibrationRecord* record);
Status ReadCalibrationFile(const std::string& path, CalibrationRecord* record);

// A two-axis calibration's parameters and covariance in parameter_order's order (bias_x,
// scale_x, bias_y, scale_y: the baseline's, estimation/tilt_table/baseline_parameters.h); fails,
// naming `path`, for another geometry.
Status TwoAxisBaseline(const CalibrationRecord& record, const std::string& path,
                       Eigen::Vector4d* parameters, Eigen::Matrix4d* covariance);

// A triad calibration's parameters (models/triad.h's block order), covariance and output
// unit; fails, naming `path`, for another geometry.
Status TriadCalibration(const CalibrationRecord& record, const std::string& path,
                        TriadParameters* parameters, Eigen::MatrixXd* covariance,
                        TriadOutputUnit* unit);

}  // namespace accelcal

#endif  // ACCELCAL_IO_CALIBRATION_FILE_H_
