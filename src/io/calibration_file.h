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
// Version 2: the model discovery settled on, when it has effect terms beyond the 9 parameters
// (issue 44, item 7). Their coefficients follow the 9 in parameter_order (the triad's registered
// effects, models/triad_effect_list.h, by name: "scale_nonlinearity_x", ...; the gyroscope's,
// models/gyroscope_effect_list.h: "gyroscope_g_sensitivity_xx", ...), with their units, stddev and
// rows of the covariance; model.effects names them after misalignment, gain and offset;
// model.effect_terms says what each is and whether apply applies it (a property of the sensor)
// or only carries it (a session's own: an offset drift over its time); and "baseline" (at the
// top level, and in the gyroscope section) holds the 9-parameter (12 for the gyroscope) model's
// fit of the same session, parameter_order, parameters, units, stddev and covariance as above,
// for comparison and for the exports whose formats cannot hold the effect terms. A file without
// effect terms is written as version 1, with "baseline": null. A version-1 reader refuses a
// version-2 file ("update accelcal") rather than apply it without its terms.
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
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/status.h"
#include "io/provenance.h"
#include "models/gyroscope.h"
#include "models/gyroscope_correction.h"
#include "models/gyroscope_units.h"
#include "models/triad.h"
#include "models/triad_correction.h"
#include "models/triad_units.h"

namespace accelcal {

constexpr char kCalibrationFormat[] = "accelcal-calibration";
// The version a file without effect terms is written as, and the one with them; the reader
// reads both.
constexpr int kCalibrationFormatVersion = 1;
constexpr int kCalibrationFormatVersionWithEffects = 2;

// The model without discovery's effect terms, fitted to the same session, written beside the
// model with them: parameter_order empty when there is none (no effect was found).
struct CalibrationBaseline {
  std::vector<std::string> parameter_order;
  Eigen::VectorXd values;
  Eigen::MatrixXd covariance;
  bool present() const { return !parameter_order.empty(); }
};

// A triad's gyroscope calibration: w = T K (u - b) (models/gyroscope.h), the block's 9
// parameters then the offsets, with their joint covariance. Build it with
// MakeGyroscopeCalibrationSection.
struct GyroscopeCalibrationSection {
  // The unit of the gyroscope's log: "count", "rad/s" or "deg/s" (models/gyroscope_units.h);
  // it sets the gains' and offsets' units.
  std::string output_unit = "count";
  // GyroscopeCalibrationParameterName(0..11), then the effect coefficients the model carries
  // (GyroscopeEffectCoefficientName, in the block's order; none for the 12-unknown model).
  std::vector<std::string> parameter_order;
  Eigen::VectorXd values;        // parameter_order's order
  Eigen::MatrixXd covariance;    // parameter_order's order
  CalibrationBaseline baseline;  // the 12 unknowns' fit, when effect terms are carried
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
// The same with effect terms: `effects` the coefficients carried (indices into
// models/gyroscope_effect_list.h's block, in its order), their values in `effect_values`, and
// `covariance` (12 + effects.size()) square in the section's order.
Status MakeGyroscopeCalibrationSection(const GyroscopeParameters& parameters,
                                       const GyroscopeOffset& offset,
                                       const std::vector<int>& effects,
                                       const GyroscopeEffectCoefficients& effect_values,
                                       const Eigen::MatrixXd& covariance, GyroscopeOutputUnit unit,
                                       GyroscopeCalibrationSection* section);

// The section's block, offset, covariance and unit, for a reader that applies the 12-unknown
// model only; fails, naming the terms, for a section with effect terms (use
// GyroscopeCalibrationModelOf, or the section's baseline).
Status GyroscopeCalibration(const GyroscopeCalibrationSection& section,
                            GyroscopeParameters* parameters, GyroscopeOffset* offset,
                            Eigen::MatrixXd* covariance, GyroscopeOutputUnit* unit);
// The 12 unknowns' fit of the session: the section's own without effect terms, else its
// baseline (for the exports whose formats hold the 12 only). *from_baseline says which.
Status GyroscopeBaselineCalibration(const GyroscopeCalibrationSection& section,
                                    GyroscopeParameters* parameters, GyroscopeOffset* offset,
                                    Eigen::MatrixXd* covariance, GyroscopeOutputUnit* unit,
                                    bool* from_baseline);
// The section as a correction applies it, effect terms included (models/gyroscope_correction.h).
Status GyroscopeCalibrationModelOf(const GyroscopeCalibrationSection& section,
                                   GyroscopeCalibrationModel* model);

// A calibration: parameters by name with their joint covariance, under a sensor geometry.
struct CalibrationRecord {
  std::string geometry = "two_axis";
  // The unit of the sensor's output the parameters map from: "m/s^2" for two_axis; for a
  // triad "count", "m/s^2" or "g" (models/triad_units.h), which sets its parameters' units.
  std::string output_unit = "m/s^2";
  // Spec names; a triad's 9, then the effect coefficients the model carries (registered names,
  // in the block's order; format_version 2).
  std::vector<std::string> parameter_order;
  Eigen::VectorXd values;
  Eigen::MatrixXd covariance;    // parameter_order's order
  CalibrationBaseline baseline;  // a triad's 9-parameter fit, when effect terms are carried
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
  // Read back only: the writer's version and command line, and the SHA-256 of each input file
  // it records by role ("log", "log_gyroscope", ...; input_files/<role>/sha256), so that a file
  // combined with it (an Allan fit for an export) can be checked against what it was made from.
  std::string written_by_version;
  std::string written_by_command_line;
  std::map<std::string, std::string> input_sha256;

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
// unit; fails, naming `path`, for another geometry, and for a calibration with effect terms
// (naming them: a reader of the 9 only would apply it without them; use
// TriadCalibrationModelOf, or TriadBaselineCalibration for the 9-parameter fit).
Status TriadCalibration(const CalibrationRecord& record, const std::string& path,
                        TriadParameters* parameters, Eigen::MatrixXd* covariance,
                        TriadOutputUnit* unit);
// The 9-parameter fit of the session: the calibration's own without effect terms, else its
// baseline (for the exports whose formats hold the 9 only). *from_baseline says which.
Status TriadBaselineCalibration(const CalibrationRecord& record, const std::string& path,
                                TriadParameters* parameters, Eigen::MatrixXd* covariance,
                                TriadOutputUnit* unit, bool* from_baseline);
// The calibration as a correction applies it, effect terms included
// (models/triad_correction.h).
Status TriadCalibrationModelOf(const CalibrationRecord& record, const std::string& path,
                               TriadCalibrationModel* model);
// The effect coefficients a record carries beyond the 9 (a triad's) or the 12 (its gyroscope
// section's), by name; empty for none.
std::vector<std::string> EffectTermNames(const CalibrationRecord& record);
std::vector<std::string> EffectTermNames(const GyroscopeCalibrationSection& section);

}  // namespace accelcal

#endif  // ACCELCAL_IO_CALIBRATION_FILE_H_
