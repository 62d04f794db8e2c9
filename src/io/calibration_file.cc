#include "io/calibration_file.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "common/format.h"
#include "io/input_file.h"
#include "io/json_file.h"
#include "models/effects.h"

namespace accelcal {
namespace {

// A number at `key` of `object`, finite, within [low, high].
Status ReadNumber(const nlohmann::json& object, const std::string& key, const std::string& where,
                  double low, double high, double* value) {
  const std::string name = where.empty() ? key : where + "/" + key;
  if (!object.is_object() || !object.contains(key)) {
    return Status::Error("the key \"" + name + "\" is missing");
  }
  const nlohmann::json& item = object.at(key);
  if (!item.is_number()) return Status::Error(name + " must be a number");
  *value = item.get<double>();
  if (!std::isfinite(*value) || *value < low || *value > high) {
    return Status::Error(name + " = " + RoundTripDouble(*value) + " is outside [" +
                         RoundTripDouble(low) + ", " + RoundTripDouble(high) + "]");
  }
  return Status::Ok();
}

Status ReadString(const nlohmann::json& object, const std::string& key, std::string* value) {
  if (!object.contains(key) || !object.at(key).is_string()) {
    return Status::Error("the key \"" + key + "\" is missing or not a string");
  }
  *value = object.at(key).get<std::string>();
  return Status::Ok();
}

Status CheckCovariance(const Eigen::MatrixXd& covariance,
                       const std::vector<std::string>& parameters) {
  for (int i = 0; i < covariance.rows(); ++i) {
    if (!(covariance(i, i) > 0.0)) {
      return Status::Error("covariance: the variance of " + parameters[i] + " is not positive");
    }
    for (int j = 0; j < i; ++j) {
      const double scale = std::sqrt(covariance(i, i) * covariance(j, j));
      if (std::abs(covariance(i, j) - covariance(j, i)) > 1e-9 * scale) {
        return Status::Error("covariance is not symmetric (" + parameters[i] + ", " +
                             parameters[j] + ")");
      }
    }
  }
  // Positive semi-definite, judged on the correlation matrix so that units do not matter.
  const Eigen::VectorXd inverse_sigma = covariance.diagonal().cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd correlation =
      inverse_sigma.asDiagonal() * covariance * inverse_sigma.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(correlation);
  if (solver.eigenvalues().minCoeff() < -1e-9) {
    return Status::Error(StringPrintf(
        "covariance is not positive semi-definite (smallest eigenvalue of the correlation "
        "matrix %.3g)",
        solver.eigenvalues().minCoeff()));
  }
  return Status::Ok();
}

Status ParseParameters(const nlohmann::json& json, const GeometryInfo& geometry,
                       CalibrationRecord* record) {
  if (!json.contains("parameter_order") || json["parameter_order"] != geometry.parameters) {
    std::string expected;
    for (const std::string& name : geometry.parameters)
      expected += (expected.empty() ? "" : ", ") + name;
    return Status::Error("parameter_order must be [" + expected + "] for geometry " +
                         record->geometry);
  }
  const size_t n = geometry.parameters.size();
  record->parameter_order = geometry.parameters;
  record->values.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const std::string& name = geometry.parameters[i];
    // Finite and of a sane size; a triad's offsets are counts of ADCs of up to 30 bits.
    const double limit = record->geometry == "triad" ? 1e9 : 1e6;
    ACCELCAL_RETURN_IF_ERROR(ReadNumber(json.value("parameters", nlohmann::json()), name,
                                        "parameters", -limit, limit, &record->values[i]));
    const nlohmann::json units = json.value("units", nlohmann::json());
    if (!units.is_object() || !units.contains(name) || units[name] != geometry.units[i]) {
      return Status::Error("units/" + name + " must be \"" + geometry.units[i] + "\", the unit " +
                           "of the model; convert the file's values rather than its label");
    }
  }
  const nlohmann::json& covariance = json.value("covariance", nlohmann::json());
  if (!covariance.is_array() || covariance.size() != n) {
    return Status::Error("covariance must be a " + std::to_string(n) + "x" + std::to_string(n) +
                         " array of arrays in parameter_order's order");
  }
  record->covariance.resize(n, n);
  for (size_t i = 0; i < n; ++i) {
    if (!covariance[i].is_array() || covariance[i].size() != n) {
      return Status::Error("covariance row " + std::to_string(i) + " must hold " +
                           std::to_string(n) + " numbers");
    }
    for (size_t j = 0; j < n; ++j) {
      const nlohmann::json& item = covariance[i][j];
      if (!item.is_number() || !std::isfinite(item.get<double>())) {
        return Status::Error(StringPrintf("covariance[%zu][%zu] is not a finite number", i, j));
      }
      record->covariance(i, j) = item.get<double>();
    }
  }
  return CheckCovariance(record->covariance, record->parameter_order);
}

// A correction divides by 1 + scale_k; no real sensor's gain is off by 90%. A triad's gains
// must be positive and agree with its output unit.
Status CheckGains(const CalibrationRecord& record) {
  if (record.geometry == "triad") {
    TriadParameters parameters;
    for (int p = 0; p < kTriadParameterCount; ++p) parameters[p] = record.values[p];
    TriadOutputUnit unit;
    ACCELCAL_RETURN_IF_ERROR(ParseTriadOutputUnit(record.output_unit, &unit));
    for (int k = 0; k < 3; ++k) {
      if (!(parameters[kTriadGainX + k] > 0.0)) {
        return Status::Error(std::string("parameters/gain_") + "xyz"[k] + " is not positive");
      }
    }
    return CheckGainsMatchUnit(parameters, unit).WithContext("parameters");
  }
  for (const char* scale : {"scale_x", "scale_y"}) {
    if (!(1.0 + record.values[record.IndexOf(scale)] > 0.1)) {
      return Status::Error(std::string("1 + ") + scale +
                           " is not above 0.1; no real sensor's gain is that far off");
    }
  }
  return Status::Ok();
}

}  // namespace

int CalibrationRecord::IndexOf(const std::string& name) const {
  for (size_t i = 0; i < parameter_order.size(); ++i) {
    if (parameter_order[i] == name) return static_cast<int>(i);
  }
  return -1;
}

Status GeometryOf(const std::string& geometry, const std::string& output_unit, GeometryInfo* info) {
  *info = GeometryInfo();
  if (geometry == "two_axis") {
    if (output_unit != "m/s^2") {
      return Status::Error("the two-axis geometry's outputs are in m/s^2, not '" + output_unit +
                           "'");
    }
    for (const Parameter parameter :
         {Parameter::kBiasX, Parameter::kScaleX, Parameter::kBiasY, Parameter::kScaleY}) {
      info->parameters.push_back(Info(parameter).name);
      info->units.push_back(Info(parameter).unit);
    }
    info->axes = {"x", "y"};
    info->effects = {"bias", "scale"};
    info->measurement = "m_k = (1 + scale_k) a_k + bias_k + noise_k, k = x, y";
    info->correction = "a_k = (m_k - bias_k) / (1 + scale_k)";
    info->conventions =
        "m_k: the axis's output and a_k: the true specific force along axis k, both in m/s^2; "
        "on the tilt table a_x = -g sin(theta), a_y = -g cos(theta) (spec/error-model.md); "
        "noise_k white, of variance noise_variance.k";
    return Status::Ok();
  }
  if (geometry == "triad") {
    TriadOutputUnit unit;
    ACCELCAL_RETURN_IF_ERROR(ParseTriadOutputUnit(output_unit, &unit).WithContext("output_unit"));
    for (int p = 0; p < kTriadParameterCount; ++p) {
      info->parameters.push_back(TriadParameterInfos()[p].name);
      info->units.push_back(TriadParameterUnit(p, unit));
    }
    info->axes = {"x", "y", "z"};
    info->effects = {"misalignment", "gain", "offset"};
    info->measurement = "u = K^-1 T^-1 a + b + noise (docs/triad.md)";
    info->correction =
        "a = T K (u - b), T = [[1, -misalignment_yz, misalignment_zy], [0, 1, "
        "-misalignment_zx], [0, 0, 1]], K = diag(gain_x, gain_y, gain_z), b = (offset_x, "
        "offset_y, offset_z)";
    info->conventions =
        "u: the triad's output in output_unit; a: specific force in m/s^2 in the frame whose x "
        "is the x sensing axis and whose y lies in the plane of the x and y sensing axes; noise "
        "white, of variance noise_variance.k per sample (output_unit squared)";
    return Status::Ok();
  }
  return Status::Error("unknown sensor geometry '" + geometry + "' (known: two_axis, triad)");
}

nlohmann::json CalibrationJson(const CalibrationRecord& record) {
  GeometryInfo geometry;
  const bool known = GeometryOf(record.geometry, record.output_unit, &geometry).ok();
  nlohmann::json parameters = nlohmann::json::object();
  nlohmann::json units = nlohmann::json::object();
  nlohmann::json stddev = nlohmann::json::object();
  nlohmann::json covariance = nlohmann::json::array();
  for (int i = 0; i < record.values.size(); ++i) {
    const std::string& name = record.parameter_order[i];
    parameters[name] = record.values[i];
    units[name] = known ? geometry.units[i] : "";
    stddev[name] = std::sqrt(record.covariance(i, i));
    nlohmann::json row = nlohmann::json::array();
    for (int j = 0; j < record.values.size(); ++j) row.push_back(record.covariance(i, j));
    covariance.push_back(row);
  }
  nlohmann::json noise = {{"unit", "(" + record.output_unit + ")^2"},
                          {"from", record.noise_variance_from}};
  for (size_t k = 0; k < record.noise_variance.size() && k < geometry.axes.size(); ++k) {
    noise[geometry.axes[k]] = record.noise_variance[k];
  }
  nlohmann::json json = {{"format", kCalibrationFormat},
                         {"format_version", kCalibrationFormatVersion},
                         {"model",
                          {{"geometry", record.geometry},
                           {"axes", geometry.axes},
                           {"effects", geometry.effects},
                           {"measurement", known ? geometry.measurement : ""},
                           {"correction", known ? geometry.correction : ""},
                           {"output_unit", record.output_unit},
                           {"conventions", known ? geometry.conventions : ""},
                           {"document", "docs/calibration.md"}}},
                         {"gravity_mps2", record.gravity_mps2},
                         {"parameter_order", record.parameter_order},
                         {"parameters", parameters},
                         {"units", units},
                         {"stddev", stddev},
                         {"covariance", covariance},
                         {"noise_variance", noise},
                         {"fit", record.fit},
                         {"created_utc", UtcNow("%Y-%m-%dT%H:%M:%SZ")}};
  json["poorly_determined"] = record.poorly_determined;
  AddProvenanceJson(record.source, &json);
  return json;
}

namespace {

// The optional list of poorly determined parameters: absent (files written before it), null
// (not assessed: a two-axis calibration), or a list of objects whose `parameter` names one of the
// file's parameters.
Status ReadPoorlyDetermined(const nlohmann::json& json, CalibrationRecord* parsed) {
  if (!json.contains("poorly_determined") || json["poorly_determined"].is_null())
    return Status::Ok();
  const nlohmann::json& list = json["poorly_determined"];
  if (!list.is_array())
    return Status::Error("\"poorly_determined\" must be a list of {parameter, reason, ...}");
  for (const nlohmann::json& entry : list) {
    if (!entry.is_object() || !entry.contains("parameter") || !entry["parameter"].is_string() ||
        parsed->IndexOf(entry["parameter"].get<std::string>()) < 0) {
      return Status::Error(
          "\"poorly_determined\" holds an entry that does not name a parameter of the file: " +
          entry.dump());
    }
  }
  parsed->poorly_determined = list;
  return Status::Ok();
}

}  // namespace

Status ParseCalibration(const std::string& text, const std::string& path,
                        CalibrationRecord* record) {
  nlohmann::json json;
  ACCELCAL_RETURN_IF_ERROR(ParseJsonStrict(text, &json).WithContext(path));
  auto in_file = [&path](const Status& status) { return status.WithContext(path); };
  if (!json.is_object() || json.value("format", "") != kCalibrationFormat) {
    return Status::Error(path + ": not an accelcal calibration file (\"format\" is not \"" +
                         kCalibrationFormat + "\"); write one with calibrate");
  }
  if (!json.contains("format_version") || !json["format_version"].is_number_integer()) {
    return Status::Error(path + ": \"format_version\" is missing or not an integer");
  }
  const int version = json["format_version"].get<int>();
  if (version != kCalibrationFormatVersion) {
    return Status::Error(path + ": format_version " + std::to_string(version) +
                         ", but this accelcal reads version " +
                         std::to_string(kCalibrationFormatVersion) +
                         (version > kCalibrationFormatVersion ? "; update accelcal" : ""));
  }
  CalibrationRecord parsed;
  const nlohmann::json model = json.value("model", nlohmann::json::object());
  if (!model.is_object()) return Status::Error(path + ": \"model\" must be an object");
  ACCELCAL_RETURN_IF_ERROR(in_file(ReadString(model, "geometry", &parsed.geometry)));
  // Version 1 files of the two-axis geometry written before the triad have no output_unit:
  // theirs is m/s^2.
  if (model.contains("output_unit") || parsed.geometry != "two_axis") {
    ACCELCAL_RETURN_IF_ERROR(
        in_file(ReadString(model, "output_unit", &parsed.output_unit).WithContext("model")));
  }
  GeometryInfo geometry;
  ACCELCAL_RETURN_IF_ERROR(
      in_file(GeometryOf(parsed.geometry, parsed.output_unit, &geometry).WithContext("model")));
  ACCELCAL_RETURN_IF_ERROR(in_file(ParseParameters(json, geometry, &parsed)));
  ACCELCAL_RETURN_IF_ERROR(in_file(CheckGains(parsed)));
  ACCELCAL_RETURN_IF_ERROR(
      in_file(ReadNumber(json, "gravity_mps2", "", 1.0, 100.0, &parsed.gravity_mps2)));
  const nlohmann::json noise = json.value("noise_variance", nlohmann::json());
  for (const std::string& axis : geometry.axes) {
    double variance = 0.0;
    ACCELCAL_RETURN_IF_ERROR(
        in_file(ReadNumber(noise, axis, "noise_variance", 1e-12, 1e4, &variance)));
    parsed.noise_variance.push_back(variance);
  }
  parsed.noise_variance_from = noise.value("from", "");
  parsed.fit = json.value("fit", nlohmann::json::object());
  ACCELCAL_RETURN_IF_ERROR(in_file(ReadPoorlyDetermined(json, &parsed)));
  parsed.created_utc = json.value("created_utc", "");
  parsed.written_by_version = json.value("accelcal_version", "");
  parsed.written_by_command_line = json.value("command_line", "");
  *record = std::move(parsed);
  return Status::Ok();
}

Status TwoAxisBaseline(const CalibrationRecord& record, const std::string& path,
                       Eigen::Vector4d* parameters, Eigen::Matrix4d* covariance) {
  if (record.geometry != "two_axis" || record.values.size() != 4) {
    return Status::Error(path +
                         ": a two-axis (x, y) calibration is needed; this one's geometry is " +
                         record.geometry);
  }
  *parameters = record.values;
  *covariance = record.covariance;
  return Status::Ok();
}

Status TriadCalibration(const CalibrationRecord& record, const std::string& path,
                        TriadParameters* parameters, Eigen::MatrixXd* covariance,
                        TriadOutputUnit* unit) {
  if (record.geometry != "triad" || record.values.size() != kTriadParameterCount) {
    return Status::Error(path +
                         ": a triad (x, y, z) calibration is needed; this one's geometry is " +
                         record.geometry);
  }
  for (int p = 0; p < kTriadParameterCount; ++p) (*parameters)[p] = record.values[p];
  *covariance = record.covariance;
  return ParseTriadOutputUnit(record.output_unit, unit).WithContext(path);
}

Status ReadCalibrationFile(const std::string& path, CalibrationRecord* record) {
  std::string text;
  ACCELCAL_RETURN_IF_ERROR(
      ReadInputText(path, kMaxConditionsFileBytes, "a calibration file", &text).WithContext(path));
  return ParseCalibration(text, path, record);
}

}  // namespace accelcal
