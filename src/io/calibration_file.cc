#include "io/calibration_file.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>

#include "common/format.h"
#include "io/input_file.h"
#include "io/input_text.h"
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

// A block of named parameters as the file writes them: `parameter_order`, `parameters`,
// `units`, `stddev` and `covariance` of one object (the file's top level for the sensor of its
// geometry, the "gyroscope" object for a triad's gyroscope). Messages name its keys after
// `prefix` ("" or "gyroscope/").
struct ParameterBlock {
  std::string prefix;
  std::string owner;  // whose parameter_order it is: "geometry triad", "the gyroscope section"
  std::vector<std::string> names;
  std::vector<std::string> units;
  double limit = 1e6;  // |value| at most: finite and of a sane size
  // A hand-written file of version 1 may omit the accelerometer's stddev (it repeats the
  // covariance); the gyroscope's section came with it from the start.
  bool stddev_required = false;
};

// The gyroscope section's model.measurement, and the length of its equation: "w = T K (u - b)".
constexpr char kGyroscopeMeasurement[] =
    "w = T K (u - b), T = [[1, -gyroscope_misalignment_yz, gyroscope_misalignment_zy], "
    "[gyroscope_misalignment_xz, 1, -gyroscope_misalignment_zx], [-gyroscope_misalignment_xy, "
    "gyroscope_misalignment_yx, 1]], K = diag(gyroscope_gain_x, gyroscope_gain_y, "
    "gyroscope_gain_z), b = (gyroscope_offset_x, gyroscope_offset_y, gyroscope_offset_z)";
constexpr size_t kGyroscopeEquationLength = 15;

// The relative tolerance between a stddev and the square root of its variance: the writer
// writes both from one double, so only an edit of one of them sets them apart.
constexpr double kStddevTolerance = 1e-6;

Status CheckCovariance(const Eigen::MatrixXd& covariance,
                       const std::vector<std::string>& parameters, const std::string& prefix) {
  for (int i = 0; i < covariance.rows(); ++i) {
    if (!(covariance(i, i) > 0.0)) {
      return Status::Error(prefix + "covariance: the variance of " + parameters[i] +
                           " is not positive");
    }
    for (int j = 0; j < i; ++j) {
      const double scale = std::sqrt(covariance(i, i) * covariance(j, j));
      if (std::abs(covariance(i, j) - covariance(j, i)) > 1e-9 * scale) {
        return Status::Error(prefix + "covariance is not symmetric (" + parameters[i] + ", " +
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
    return Status::Error(prefix + StringPrintf("covariance is not positive semi-definite (smallest "
                                               "eigenvalue of the correlation matrix %.3g)",
                                               solver.eigenvalues().minCoeff()));
  }
  return Status::Ok();
}

// Each key of the object at `key` (when it is one) names a parameter of the block.
Status CheckKnownNames(const nlohmann::json& object, const std::string& key,
                       const ParameterBlock& block) {
  const nlohmann::json& map = object.contains(key) ? object.at(key) : nlohmann::json();
  if (!map.is_object()) return Status::Ok();  // its parameters' reads say what is wrong
  for (auto it = map.begin(); it != map.end(); ++it) {
    if (std::find(block.names.begin(), block.names.end(), it.key()) == block.names.end()) {
      return Status::Error(block.prefix + key + "/" + EchoInput(it.key()) +
                           ": not a parameter of " + block.owner + " (parameter_order names them)");
    }
  }
  return Status::Ok();
}

// A key of the model's text, when the file gives it, against what format_version 1 writes for
// the geometry: `exact`, or its start `prefix` (the gyroscope's equation, which a hand-written
// section may give without the matrices spelled out).
Status CheckModelKey(const nlohmann::json& model, const std::string& where, const char* key,
                     const nlohmann::json& written, size_t prefix = 0) {
  if (!model.is_object() || !model.contains(key)) return Status::Ok();
  const nlohmann::json& given = model.at(key);
  const bool agrees = prefix == 0 ? given == written
                                  : given.is_string() && written.is_string() &&
                                        given.get<std::string>().compare(
                                            0, prefix, written.get<std::string>(), 0, prefix) == 0;
  if (agrees) return Status::Ok();
  return Status::Error(where + "model/" + key + " is " + EchoInput(given.dump()) +
                       ", but format_version 1 writes " + EchoInput(written.dump()) +
                       ": the file describes another model than the one its parameters are read "
                       "with; write it again with accelcal, or remove the key");
}

// stddev, when given (or required), is the square root of the covariance's diagonal.
Status CheckStddev(const nlohmann::json& object, const ParameterBlock& block,
                   const Eigen::MatrixXd& covariance) {
  if (!object.contains("stddev") && !block.stddev_required) return Status::Ok();
  const nlohmann::json& stddev = object.contains("stddev") ? object.at("stddev") : nlohmann::json();
  if (!stddev.is_object()) {
    return Status::Error(block.prefix + "stddev must be an object: each parameter's standard " +
                         "deviation, the square root of its variance in covariance");
  }
  for (size_t i = 0; i < block.names.size(); ++i) {
    const std::string key = block.prefix + "stddev/" + block.names[i];
    if (!stddev.contains(block.names[i])) {
      return Status::Error("the key \"" + key + "\" is missing");
    }
    const nlohmann::json& item = stddev.at(block.names[i]);
    if (!item.is_number() || !std::isfinite(item.get<double>())) {
      return Status::Error(key + " must be a finite number");
    }
    const double value = item.get<double>();
    const double sigma = std::sqrt(covariance(i, i));
    if (!(std::abs(value - sigma) <= kStddevTolerance * sigma)) {
      return Status::Error(StringPrintf(
          "%sstddev/%s = %s contradicts %scovariance[%zu][%zu] = %s, whose square root is %s "
          "(relative difference %.3g, more than %g): one of the two was edited; correct it",
          block.prefix.c_str(), block.names[i].c_str(), RoundTripDouble(value).c_str(),
          block.prefix.c_str(), i, i, RoundTripDouble(covariance(i, i)).c_str(),
          RoundTripDouble(sigma).c_str(), std::abs(value - sigma) / sigma, kStddevTolerance));
    }
  }
  return CheckKnownNames(object, "stddev", block);
}

Status ParseParameterBlock(const nlohmann::json& object, const ParameterBlock& block,
                           Eigen::VectorXd* values, Eigen::MatrixXd* covariance) {
  if (!object.contains("parameter_order") || object["parameter_order"] != block.names) {
    std::string expected;
    for (const std::string& name : block.names) expected += (expected.empty() ? "" : ", ") + name;
    return Status::Error(block.prefix + "parameter_order must be [" + expected + "] for " +
                         block.owner);
  }
  const size_t n = block.names.size();
  values->resize(n);
  const nlohmann::json parameters = object.value("parameters", nlohmann::json());
  const nlohmann::json units = object.value("units", nlohmann::json());
  for (size_t i = 0; i < n; ++i) {
    const std::string& name = block.names[i];
    ACCELCAL_RETURN_IF_ERROR(ReadNumber(parameters, name, block.prefix + "parameters", -block.limit,
                                        block.limit, &(*values)[i]));
    if (!units.is_object() || !units.contains(name) || units[name] != block.units[i]) {
      return Status::Error(block.prefix + "units/" + name + " must be \"" + block.units[i] +
                           "\", the unit of the model; convert the file's values rather than " +
                           "its label");
    }
  }
  ACCELCAL_RETURN_IF_ERROR(CheckKnownNames(object, "parameters", block));
  ACCELCAL_RETURN_IF_ERROR(CheckKnownNames(object, "units", block));
  const nlohmann::json& matrix = object.value("covariance", nlohmann::json());
  if (!matrix.is_array() || matrix.size() != n) {
    return Status::Error(block.prefix + "covariance must be a " + std::to_string(n) + "x" +
                         std::to_string(n) + " array of arrays in parameter_order's order");
  }
  covariance->resize(n, n);
  for (size_t i = 0; i < n; ++i) {
    if (!matrix[i].is_array() || matrix[i].size() != n) {
      return Status::Error(block.prefix + "covariance row " + std::to_string(i) + " must hold " +
                           std::to_string(n) + " numbers");
    }
    for (size_t j = 0; j < n; ++j) {
      const nlohmann::json& item = matrix[i][j];
      if (!item.is_number() || !std::isfinite(item.get<double>())) {
        return Status::Error(block.prefix +
                             StringPrintf("covariance[%zu][%zu] is not a finite number", i, j));
      }
      (*covariance)(i, j) = item.get<double>();
    }
  }
  ACCELCAL_RETURN_IF_ERROR(CheckCovariance(*covariance, block.names, block.prefix));
  return CheckStddev(object, block, *covariance);
}

// The keys ParseParameterBlock reads, written.
nlohmann::json ParameterBlockJson(const std::vector<std::string>& names,
                                  const std::vector<std::string>& units,
                                  const Eigen::VectorXd& values,
                                  const Eigen::MatrixXd& covariance) {
  nlohmann::json parameters = nlohmann::json::object();
  nlohmann::json unit_of = nlohmann::json::object();
  nlohmann::json stddev = nlohmann::json::object();
  nlohmann::json matrix = nlohmann::json::array();
  for (int i = 0; i < values.size(); ++i) {
    const std::string& name = names[i];
    parameters[name] = values[i];
    unit_of[name] = i < static_cast<int>(units.size()) ? units[i] : "";
    stddev[name] = std::sqrt(covariance(i, i));
    nlohmann::json row = nlohmann::json::array();
    for (int j = 0; j < values.size(); ++j) row.push_back(covariance(i, j));
    matrix.push_back(row);
  }
  return {{"parameter_order", names},
          {"parameters", parameters},
          {"units", unit_of},
          {"stddev", stddev},
          {"covariance", matrix}};
}

// The gyroscope section's block, for outputs in `unit`. Offsets in counts reach 2^30 as the
// triad's do.
ParameterBlock GyroscopeBlock(GyroscopeOutputUnit unit, const std::vector<int>& terms = {}) {
  ParameterBlock block;
  block.prefix = "gyroscope/";
  block.owner = "the gyroscope section";
  for (int p = 0; p < kGyroscopeCalibrationParameterCount; ++p) {
    block.names.push_back(GyroscopeCalibrationParameterName(p));
    block.units.push_back(GyroscopeParameterUnit(p, unit));
  }
  for (const int c : terms) {
    block.names.push_back(GyroscopeEffectCoefficientName(c));
    block.units.push_back(GyroscopeEffectCoefficientUnit(c));
  }
  block.limit = 1e9;
  block.stddev_required = true;
  return block;
}

// The effect terms `object`'s parameter_order lists after its first `base` names: each a
// coefficient `index_of` knows (-1: none), once, in the block's order; only in a file of
// format_version 2. Nothing when parameter_order is not a list longer than `base` (its own
// check says what is wrong with it).
Status ReadEffectTerms(const nlohmann::json& object, size_t base, const std::string& prefix,
                       int version, const std::function<int(const std::string&)>& index_of,
                       std::vector<int>* terms) {
  terms->clear();
  const nlohmann::json& order =
      object.contains("parameter_order") ? object.at("parameter_order") : nlohmann::json();
  if (!order.is_array() || order.size() <= base) return Status::Ok();
  if (version < kCalibrationFormatVersionWithEffects) {
    return Status::Error(StringPrintf(
        "%sparameter_order lists %zu names after the model's %zu: effect terms come only in a "
        "file of format_version %d",
        prefix.c_str(), order.size() - base, base, kCalibrationFormatVersionWithEffects));
  }
  for (size_t i = base; i < order.size(); ++i) {
    const int c = order[i].is_string() ? index_of(order[i].get<std::string>()) : -1;
    if (c < 0) {
      return Status::Error(prefix + "parameter_order[" + std::to_string(i) +
                           "] = " + EchoInput(order[i].dump()) +
                           " is not an effect term this accelcal knows (docs/calibration.md)");
    }
    if (!terms->empty() && c <= terms->back()) {
      return Status::Error(prefix + "parameter_order[" + std::to_string(i) +
                           "] = " + EchoInput(order[i].dump()) +
                           ": effect terms are listed once each, in the registry's order");
    }
    terms->push_back(c);
  }
  return Status::Ok();
}

// The optional baseline of `object`: required (an object holding `block`) when the model carries
// effect terms, absent or null otherwise.
Status ReadBaseline(const nlohmann::json& object, ParameterBlock block, bool has_terms,
                    CalibrationBaseline* baseline) {
  const std::string key = block.prefix + "baseline";
  const bool given = object.contains("baseline") && !object.at("baseline").is_null();
  if (!has_terms) {
    if (given) {
      return Status::Error(key + " is given, but the model carries no effect term: a baseline " +
                           "is the model without them");
    }
    return Status::Ok();
  }
  if (!given || !object.at("baseline").is_object()) {
    return Status::Error(key + " must be an object (the model without its effect terms, fitted " +
                         "to the same session), as the writer writes it");
  }
  block.prefix = key + "/";
  block.owner = "the baseline of " + block.owner;
  baseline->parameter_order = block.names;
  return ParseParameterBlock(object.at("baseline"), block, &baseline->values,
                             &baseline->covariance);
}

// The registered triad coefficient's index by name, -1 when none.
int TriadTermIndex(const std::string& name) { return TriadEffectCoefficientIndex(name); }

// The effects a model's text names: the geometry's, then each effect of `terms` once.
std::vector<std::string> EffectsNamed(const std::vector<std::string>& geometry_effects,
                                      const std::vector<std::string>& term_effects) {
  std::vector<std::string> named = geometry_effects;
  for (const std::string& effect : term_effects)
    if (std::find(named.begin(), named.end(), effect) == named.end()) named.push_back(effect);
  return named;
}

std::vector<std::string> TriadTermEffects(const std::vector<int>& terms) {
  std::vector<std::string> effects;
  for (const int c : terms)
    effects.push_back(TriadEffectInfos()[TriadEffectCoefficientList()[c].effect].name);
  return effects;
}

std::vector<std::string> GyroscopeTermEffects(const std::vector<int>& terms) {
  std::vector<std::string> effects;
  for (const int c : terms) effects.push_back(GyroscopeEffectInfos()[GyroscopeEffectOf(c)].name);
  return effects;
}

// The indices of a record's effect terms: its names after the model's `base`.
std::vector<int> TermsOf(const std::vector<std::string>& order, size_t base,
                         const std::function<int(const std::string&)>& index_of) {
  std::vector<int> terms;
  for (size_t i = base; i < order.size(); ++i) terms.push_back(index_of(order[i]));
  return terms;
}

// The file's parameters: the geometry's, then (a triad's, version 2) its effect terms, and the
// baseline when there are some.
Status ParseParameters(const nlohmann::json& json, const GeometryInfo& geometry, int version,
                       CalibrationRecord* record) {
  ParameterBlock block;
  block.owner = "geometry " + record->geometry;
  block.names = geometry.parameters;
  block.units = geometry.units;
  // A triad's offsets are counts of ADCs of up to 30 bits.
  block.limit = record->geometry == "triad" ? 1e9 : 1e6;
  std::vector<int> terms;
  if (record->geometry == "triad") {
    ACCELCAL_RETURN_IF_ERROR(
        ReadEffectTerms(json, geometry.parameters.size(), "", version, TriadTermIndex, &terms));
  }
  const ParameterBlock without_terms = block;
  for (const int c : terms) {
    block.names.push_back(TriadEffectCoefficientList()[c].name);
    block.units.push_back(TriadEffectUnit(c, record->output_unit));
  }
  record->parameter_order = block.names;
  ACCELCAL_RETURN_IF_ERROR(ParseParameterBlock(json, block, &record->values, &record->covariance));
  const nlohmann::json model = json.value("model", nlohmann::json::object());
  ACCELCAL_RETURN_IF_ERROR(
      CheckModelKey(model, "", "effects", EffectsNamed(geometry.effects, TriadTermEffects(terms))));
  return ReadBaseline(json, without_terms, !terms.empty(), &record->baseline);
}

// A gyroscope's gains are positive (an axis wired backwards is a sign the fit should not hide,
// as the triad's) and agree with its output unit.
Status CheckGyroscopeSection(const GyroscopeCalibrationSection& section) {
  GyroscopeCalibrationModel model;
  ACCELCAL_RETURN_IF_ERROR(GyroscopeCalibrationModelOf(section, &model));
  for (int k = 0; k < 3; ++k) {
    if (!(model.parameters[kGyroscopeGainX + k] > 0.0)) {
      return Status::Error("gyroscope/parameters/" +
                           GyroscopeCalibrationParameterName(kGyroscopeGainX + k) +
                           " is not positive");
    }
  }
  return CheckGyroscopeMatchesUnit(model.parameters, model.offset, model.unit)
      .WithContext("gyroscope/parameters");
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
        "u: the triad's output in output_unit; a: specific force in m/s^2 in the frame whose z "
        "is the z sensing axis and whose y lies in the plane of the y and z sensing axes (T is "
        "upper-triangular: docs/triad.md, Frames); noise white, of variance noise_variance.k per "
        "sample (output_unit squared)";
    return Status::Ok();
  }
  return Status::Error("unknown sensor geometry '" + geometry + "' (known: two_axis, triad)");
}

namespace {

// The gyroscope section's object.
// A baseline's object, or null.
nlohmann::json BaselineJson(const CalibrationBaseline& baseline,
                            const std::vector<std::string>& units, const char* note) {
  if (!baseline.present()) return nullptr;
  nlohmann::json json =
      ParameterBlockJson(baseline.parameter_order, units, baseline.values, baseline.covariance);
  json["note"] = note;
  return json;
}

// What each effect term is and whether apply applies it, for a reader of the file.
nlohmann::json EffectTermsJson(const std::vector<std::string>& effects,
                               const std::vector<std::string>& meanings,
                               const std::vector<const char*>& session_only) {
  nlohmann::json list = nlohmann::json::array();
  for (size_t e = 0; e < effects.size(); ++e) {
    bool listed = false;
    for (const nlohmann::json& item : list) listed = listed || item["effect"] == effects[e];
    if (listed) continue;
    list.push_back(
        {{"effect", effects[e]},
         {"meaning", meanings[e]},
         {"applied_by_apply", session_only[e] == nullptr},
         {"why_not_applied",
          session_only[e] == nullptr ? nlohmann::json(nullptr) : nlohmann::json(session_only[e])}});
  }
  return list;
}

nlohmann::json GyroscopeSectionJson(const GyroscopeCalibrationSection& section) {
  GyroscopeOutputUnit unit;
  const bool known = ParseGyroscopeOutputUnit(section.output_unit, &unit).ok();
  const std::vector<int> terms =
      TermsOf(section.parameter_order, kGyroscopeCalibrationParameterCount,
              GyroscopeEffectCoefficientIndex);
  nlohmann::json json =
      ParameterBlockJson(section.parameter_order,
                         known ? GyroscopeBlock(unit, terms).units : std::vector<std::string>(),
                         section.values, section.covariance);
  json["model"] = {
      {"measurement", kGyroscopeMeasurement},
      {"conventions",
       "u: the gyroscope's output in output_unit; w: angular rate in rad/s in the "
       "accelerometer's frame (model.conventions: z along the accelerometer's z sensing axis, y "
       "in the plane of its y and z sensing axes); misalignment angles in rad, "
       "gyroscope_misalignment_ij the i sensing axis rotated about the j axis (imu_tk's mis_ij); "
       "gains in rad/s per unit of output; offsets, the output at zero rate, in output_unit"},
      {"document", "docs/calibration.md, docs/gyroscope.md"}};
  if (!terms.empty()) {
    const std::vector<std::string> effects = GyroscopeTermEffects(terms);
    std::vector<std::string> meanings;
    std::vector<const char*> session_only;
    for (const std::string& effect : effects) {
      const GyroscopeEffectInfo& info = GyroscopeEffectInfos()[GyroscopeEffectIndex(effect)];
      meanings.push_back(info.meaning);
      session_only.push_back(info.session_only);
    }
    json["model"]["effects"] = EffectsNamed({}, effects);
    json["model"]["effect_terms"] = EffectTermsJson(effects, meanings, session_only);
    json["model"]["measurement_with_effects"] =
        "u'_k = u_k + gyroscope_time_offset du_k/dt; v_k = gyroscope_gain_k (u'_k - "
        "gyroscope_offset_k); v'_k = v_k + gyroscope_scale_asymmetry_k |v_k| + "
        "gyroscope_scale_nonlinearity_k v_k^2; w = T v' - G f, G the 3x3 "
        "gyroscope_g_sensitivity_ij (row i, column j) and f the specific force the calibrated "
        "accelerometer measures; each term 0 when the file does not carry it (docs/gyroscope.md)";
  }
  json["baseline"] = BaselineJson(
      section.baseline, known ? GyroscopeBlock(unit).units : std::vector<std::string>(),
      "the 12 unknowns' fit of the same session, without the effect terms: for comparison, and "
      "for formats that hold the 12 only");
  json["output_unit"] = section.output_unit;
  json["fit"] = section.fit;
  json["poorly_determined"] = section.poorly_determined;
  return json;
}

}  // namespace

nlohmann::json CalibrationJson(const CalibrationRecord& record) {
  GeometryInfo geometry;
  const bool known = GeometryOf(record.geometry, record.output_unit, &geometry).ok();
  nlohmann::json noise = {{"unit", "(" + record.output_unit + ")^2"},
                          {"from", record.noise_variance_from}};
  for (size_t k = 0; k < record.noise_variance.size() && k < geometry.axes.size(); ++k) {
    noise[geometry.axes[k]] = record.noise_variance[k];
  }
  const std::vector<int> terms =
      record.geometry == "triad"
          ? TermsOf(record.parameter_order, kTriadParameterCount, TriadTermIndex)
          : std::vector<int>();
  std::vector<std::string> units = geometry.units;
  for (const int c : terms) units.push_back(TriadEffectUnit(c, record.output_unit));
  const bool with_terms =
      !terms.empty() || (record.has_gyroscope && !EffectTermNames(record.gyroscope).empty());
  nlohmann::json json =
      ParameterBlockJson(record.parameter_order, units, record.values, record.covariance);
  json.update({{"format", kCalibrationFormat},
               {"format_version",
                with_terms ? kCalibrationFormatVersionWithEffects : kCalibrationFormatVersion},
               {"model",
                {{"geometry", record.geometry},
                 {"axes", geometry.axes},
                 {"effects", EffectsNamed(geometry.effects, TriadTermEffects(terms))},
                 {"measurement", known ? geometry.measurement : ""},
                 {"correction", known ? geometry.correction : ""},
                 {"output_unit", record.output_unit},
                 {"conventions", known ? geometry.conventions : ""},
                 {"document", "docs/calibration.md"}}},
               {"gravity_mps2", record.gravity_mps2},
               {"noise_variance", noise},
               {"fit", record.fit},
               {"created_utc", UtcNow("%Y-%m-%dT%H:%M:%SZ")}});
  if (!terms.empty()) {
    std::vector<std::string> meanings;
    std::vector<const char*> session_only;
    for (const int c : terms) {
      const TriadEffectInfo& info = TriadEffectInfos()[TriadEffectCoefficientList()[c].effect];
      meanings.push_back(info.meaning);
      session_only.push_back(info.session_only);
    }
    json["model"]["effect_terms"] =
        EffectTermsJson(TriadTermEffects(terms), meanings, session_only);
  }
  json["baseline"] =
      BaselineJson(record.baseline, geometry.units,
                   "the 9-parameter model's fit of the same session, without the effect terms: for "
                   "comparison, and for formats that hold the 9 only");
  json["poorly_determined"] = record.poorly_determined;
  json["gyroscope"] =
      record.has_gyroscope ? GyroscopeSectionJson(record.gyroscope) : nlohmann::json(nullptr);
  AddProvenanceJson(record.source, &json);
  return json;
}

namespace {

// The optional list of poorly determined parameters of `object` (the file, or its gyroscope
// section, named by `prefix`): absent (files written before it), null (not assessed: a two-axis
// calibration), or a list of objects whose `parameter` names one of `parameters`.
Status ReadPoorlyDetermined(const nlohmann::json& object, const std::string& prefix,
                            const std::vector<std::string>& parameters, nlohmann::json* read) {
  if (!object.contains("poorly_determined") || object["poorly_determined"].is_null())
    return Status::Ok();
  const nlohmann::json& list = object["poorly_determined"];
  const std::string key = "\"" + prefix + "poorly_determined\"";
  if (!list.is_array()) return Status::Error(key + " must be a list of {parameter, reason, ...}");
  for (const nlohmann::json& entry : list) {
    if (!entry.is_object() || !entry.contains("parameter") || !entry["parameter"].is_string() ||
        std::find(parameters.begin(), parameters.end(), entry["parameter"].get<std::string>()) ==
            parameters.end()) {
      return Status::Error(key + " holds an entry that does not name a parameter of " +
                           (prefix.empty() ? "the file" : "the gyroscope section") + ": " +
                           entry.dump());
    }
  }
  *read = list;
  return Status::Ok();
}

// The optional gyroscope section: absent (files written before it) or null (none), or a
// triad's gyroscope, checked as the accelerometer's part is.
Status ReadGyroscopeSection(const nlohmann::json& json, int version, CalibrationRecord* parsed) {
  if (!json.contains("gyroscope") || json["gyroscope"].is_null()) return Status::Ok();
  const nlohmann::json& object = json["gyroscope"];
  if (!object.is_object()) {
    return Status::Error("\"gyroscope\" must be an object (the gyroscope's calibration) or null");
  }
  if (parsed->geometry != "triad") {
    return Status::Error(
        "\"gyroscope\": a gyroscope's calibration belongs to a triad's file; "
        "this one's geometry is " +
        parsed->geometry);
  }
  GyroscopeCalibrationSection section;
  if (!object.contains("output_unit") || !object["output_unit"].is_string()) {
    return Status::Error("the key \"gyroscope/output_unit\" is missing or not a string");
  }
  ACCELCAL_RETURN_IF_ERROR(CheckModelKey(object.value("model", nlohmann::json()), "gyroscope/",
                                         "measurement", kGyroscopeMeasurement,
                                         kGyroscopeEquationLength));
  section.output_unit = object["output_unit"].get<std::string>();
  GyroscopeOutputUnit unit;  // the file's text echoed fit for one line: no unit is changed by it
  ACCELCAL_RETURN_IF_ERROR(ParseGyroscopeOutputUnit(EchoInput(section.output_unit), &unit)
                               .WithContext("gyroscope/output_unit"));
  std::vector<int> terms;
  ACCELCAL_RETURN_IF_ERROR(ReadEffectTerms(object, kGyroscopeCalibrationParameterCount,
                                           "gyroscope/", version, GyroscopeEffectCoefficientIndex,
                                           &terms));
  for (size_t t = 0; t < terms.size(); ++t) {
    const GyroscopeEffectInfo& info = GyroscopeEffectInfos()[GyroscopeEffectOf(terms[t])];
    if (info.not_a_candidate != nullptr) {
      return Status::Error(StringPrintf("gyroscope/parameter_order[%zu] = \"%s\": ",
                                        kGyroscopeCalibrationParameterCount + t,
                                        GyroscopeEffectCoefficientName(terms[t]).c_str()) +
                           "a calibration carries the sensor's terms, and this is not one (" +
                           info.not_a_candidate + "); remove it");
    }
  }
  const ParameterBlock block = GyroscopeBlock(unit, terms);
  section.parameter_order = block.names;
  ACCELCAL_RETURN_IF_ERROR(
      ParseParameterBlock(object, block, &section.values, &section.covariance));
  ACCELCAL_RETURN_IF_ERROR(
      ReadBaseline(object, GyroscopeBlock(unit), !terms.empty(), &section.baseline));
  ACCELCAL_RETURN_IF_ERROR(CheckGyroscopeSection(section));
  section.fit = object.value("fit", nlohmann::json::object());
  if (!section.fit.is_object()) return Status::Error("gyroscope/fit must be an object");
  ACCELCAL_RETURN_IF_ERROR(ReadPoorlyDetermined(object, "gyroscope/", section.parameter_order,
                                                &section.poorly_determined));
  parsed->has_gyroscope = true;
  parsed->gyroscope = std::move(section);
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
  if (version < kCalibrationFormatVersion || version > kCalibrationFormatVersionWithEffects) {
    return Status::Error(
        path + ": format_version " + std::to_string(version) +
        ", but this accelcal reads versions " + std::to_string(kCalibrationFormatVersion) +
        " and " + std::to_string(kCalibrationFormatVersionWithEffects) +
        (version > kCalibrationFormatVersionWithEffects ? "; update accelcal" : ""));
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
  ACCELCAL_RETURN_IF_ERROR(in_file(CheckModelKey(model, "", "measurement", geometry.measurement)));
  ACCELCAL_RETURN_IF_ERROR(in_file(CheckModelKey(model, "", "correction", geometry.correction)));
  ACCELCAL_RETURN_IF_ERROR(in_file(CheckModelKey(model, "", "axes", geometry.axes)));
  ACCELCAL_RETURN_IF_ERROR(in_file(ParseParameters(json, geometry, version, &parsed)));
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
  ACCELCAL_RETURN_IF_ERROR(
      in_file(ReadPoorlyDetermined(json, "", parsed.parameter_order, &parsed.poorly_determined)));
  ACCELCAL_RETURN_IF_ERROR(in_file(ReadGyroscopeSection(json, version, &parsed)));
  if (version == kCalibrationFormatVersionWithEffects && EffectTermNames(parsed).empty() &&
      (!parsed.has_gyroscope || EffectTermNames(parsed.gyroscope).empty())) {
    return Status::Error(path +
                         ": format_version 2 is written for a model with effect terms, "
                         "but this file carries none; write it again with accelcal, or give "
                         "format_version 1");
  }
  parsed.created_utc = json.value("created_utc", "");
  parsed.written_by_version = json.value("accelcal_version", "");
  parsed.written_by_command_line = json.value("command_line", "");
  const nlohmann::json inputs = json.value("input_files", nlohmann::json::object());
  if (inputs.is_object()) {
    for (auto it = inputs.begin(); it != inputs.end(); ++it) {
      if (it.value().is_object() && it.value().contains("sha256") &&
          it.value()["sha256"].is_string())
        parsed.input_sha256[it.key()] = it.value()["sha256"].get<std::string>();
    }
  }
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

std::vector<std::string> EffectTermNames(const CalibrationRecord& record) {
  if (record.geometry != "triad" || record.parameter_order.size() <= kTriadParameterCount)
    return {};
  return std::vector<std::string>(record.parameter_order.begin() + kTriadParameterCount,
                                  record.parameter_order.end());
}

std::vector<std::string> EffectTermNames(const GyroscopeCalibrationSection& section) {
  if (section.parameter_order.size() <= kGyroscopeCalibrationParameterCount) return {};
  return std::vector<std::string>(
      section.parameter_order.begin() + kGyroscopeCalibrationParameterCount,
      section.parameter_order.end());
}

namespace {

Status NeedTriad(const CalibrationRecord& record, const std::string& path) {
  if (record.geometry != "triad" || record.values.size() < kTriadParameterCount) {
    return Status::Error(path +
                         ": a triad (x, y, z) calibration is needed; this one's geometry is " +
                         record.geometry);
  }
  return Status::Ok();
}

}  // namespace

Status TriadCalibration(const CalibrationRecord& record, const std::string& path,
                        TriadParameters* parameters, Eigen::MatrixXd* covariance,
                        TriadOutputUnit* unit) {
  ACCELCAL_RETURN_IF_ERROR(NeedTriad(record, path));
  const std::vector<std::string> terms = EffectTermNames(record);
  if (!terms.empty()) {
    return Status::Error(path + ": the calibration carries effect terms beyond the 9 parameters (" +
                         JoinStrings(terms) +
                         "), which this reader of the 9 would leave out; apply applies them");
  }
  for (int p = 0; p < kTriadParameterCount; ++p) (*parameters)[p] = record.values[p];
  *covariance = record.covariance;
  return ParseTriadOutputUnit(record.output_unit, unit).WithContext(path);
}

Status TriadBaselineCalibration(const CalibrationRecord& record, const std::string& path,
                                TriadParameters* parameters, Eigen::MatrixXd* covariance,
                                TriadOutputUnit* unit, bool* from_baseline) {
  ACCELCAL_RETURN_IF_ERROR(NeedTriad(record, path));
  *from_baseline = !EffectTermNames(record).empty();
  if (!*from_baseline) return TriadCalibration(record, path, parameters, covariance, unit);
  if (!record.baseline.present() || record.baseline.values.size() != kTriadParameterCount) {
    return Status::Error(path +
                         ": the calibration carries effect terms and no 9-parameter "
                         "baseline to write in a format that holds the 9 only");
  }
  for (int p = 0; p < kTriadParameterCount; ++p) (*parameters)[p] = record.baseline.values[p];
  *covariance = record.baseline.covariance;
  return ParseTriadOutputUnit(record.output_unit, unit).WithContext(path);
}

Status TriadCalibrationModelOf(const CalibrationRecord& record, const std::string& path,
                               TriadCalibrationModel* model) {
  ACCELCAL_RETURN_IF_ERROR(NeedTriad(record, path));
  *model = TriadCalibrationModel();
  ACCELCAL_RETURN_IF_ERROR(
      ParseTriadOutputUnit(record.output_unit, &model->unit).WithContext(path));
  model->gravity_mps2 = record.gravity_mps2;
  for (int p = 0; p < kTriadParameterCount; ++p) model->parameters[p] = record.values[p];
  // Unknown i of the file at its place in the correction's order (the 9, then the block).
  std::vector<int> place(record.parameter_order.size(), -1);
  for (int p = 0; p < kTriadParameterCount; ++p) place[p] = p;
  for (size_t i = kTriadParameterCount; i < record.parameter_order.size(); ++i) {
    const int c = TriadEffectCoefficientIndex(record.parameter_order[i]);
    if (c < 0) {
      return Status::Error(path + ": " + record.parameter_order[i] +
                           " is not an effect term this accelcal knows");
    }
    if (!TriadEffectAppliedInUse(c)) {
      model->effects_not_applied.push_back(c);
      continue;
    }
    model->effects[c] = record.values[i];
    model->effects_applied.push_back(c);
    place[i] = kTriadParameterCount + c;
  }
  model->covariance = Eigen::MatrixXd::Zero(kTriadCorrectionUnknowns, kTriadCorrectionUnknowns);
  for (size_t i = 0; i < place.size(); ++i) {
    for (size_t j = 0; j < place.size(); ++j) {
      if (place[i] >= 0 && place[j] >= 0)
        model->covariance(place[i], place[j]) = record.covariance(i, j);
    }
  }
  return Status::Ok();
}

Status MakeGyroscopeCalibrationSection(const GyroscopeParameters& parameters,
                                       const GyroscopeOffset& offset,
                                       const Eigen::MatrixXd& covariance, GyroscopeOutputUnit unit,
                                       GyroscopeCalibrationSection* section) {
  return MakeGyroscopeCalibrationSection(parameters, offset, {}, GyroscopeEffectCoefficients{},
                                         covariance, unit, section);
}

Status MakeGyroscopeCalibrationSection(const GyroscopeParameters& parameters,
                                       const GyroscopeOffset& offset,
                                       const std::vector<int>& effects,
                                       const GyroscopeEffectCoefficients& effect_values,
                                       const Eigen::MatrixXd& covariance, GyroscopeOutputUnit unit,
                                       GyroscopeCalibrationSection* section) {
  GyroscopeCalibrationSection made;
  made.output_unit = GyroscopeOutputUnitName(unit);
  for (size_t e = 0; e < effects.size(); ++e) {
    if (effects[e] < 0 || effects[e] >= kGyroscopeEffectCoefficientCount ||
        (e > 0 && effects[e] <= effects[e - 1])) {
      return Status::Error("gyroscope: the effect terms are not the block's coefficients in order");
    }
    if (GyroscopeEffectInfos()[GyroscopeEffectOf(effects[e])].not_a_candidate != nullptr) {
      return Status::Error("gyroscope: " + GyroscopeEffectCoefficientName(effects[e]) +
                           " is not a term of the sensor's calibration");
    }
  }
  const ParameterBlock block = GyroscopeBlock(unit, effects);
  made.parameter_order = block.names;
  const int n = static_cast<int>(block.names.size());
  if (covariance.rows() != n || covariance.cols() != n) {
    return Status::Error(StringPrintf("gyroscope/covariance is %dx%d, not %dx%d",
                                      static_cast<int>(covariance.rows()),
                                      static_cast<int>(covariance.cols()), n, n));
  }
  made.values.resize(n);
  for (int p = 0; p < kGyroscopeParameterCount; ++p) made.values[p] = parameters[p];
  for (int k = 0; k < 3; ++k) made.values[kGyroscopeCalibrationOffsetX + k] = offset[k];
  for (size_t e = 0; e < effects.size(); ++e)
    made.values[kGyroscopeCalibrationParameterCount + e] = effect_values[effects[e]];
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(made.values[i]) || std::abs(made.values[i]) > block.limit) {
      return Status::Error("gyroscope/parameters/" + block.names[i] + " = " +
                           RoundTripDouble(made.values[i]) + " is not a finite number within " +
                           RoundTripDouble(block.limit));
    }
  }
  if (!covariance.allFinite()) return Status::Error("gyroscope/covariance is not finite");
  made.covariance = covariance;
  ACCELCAL_RETURN_IF_ERROR(CheckCovariance(made.covariance, made.parameter_order, block.prefix));
  ACCELCAL_RETURN_IF_ERROR(CheckGyroscopeSection(made));
  *section = std::move(made);
  return Status::Ok();
}

Status GyroscopeCalibration(const GyroscopeCalibrationSection& section,
                            GyroscopeParameters* parameters, GyroscopeOffset* offset,
                            Eigen::MatrixXd* covariance, GyroscopeOutputUnit* unit) {
  ACCELCAL_RETURN_IF_ERROR(
      ParseGyroscopeOutputUnit(section.output_unit, unit).WithContext("gyroscope/output_unit"));
  const std::vector<std::string> terms = EffectTermNames(section);
  if (!terms.empty()) {
    return Status::Error("the gyroscope section carries effect terms beyond its 12 parameters (" +
                         JoinStrings(terms) +
                         "), which this reader of the 12 would leave out; apply applies them");
  }
  if (section.values.size() != kGyroscopeCalibrationParameterCount ||
      section.covariance.rows() != kGyroscopeCalibrationParameterCount ||
      section.covariance.cols() != kGyroscopeCalibrationParameterCount) {
    return Status::Error(
        "the gyroscope section does not hold its 12 parameters and their 12x12 covariance");
  }
  for (int p = 0; p < kGyroscopeParameterCount; ++p) (*parameters)[p] = section.values[p];
  for (int k = 0; k < 3; ++k) (*offset)[k] = section.values[kGyroscopeCalibrationOffsetX + k];
  *covariance = section.covariance;
  return Status::Ok();
}

Status ReadCalibrationFile(const std::string& path, CalibrationRecord* record) {
  std::string text;
  ACCELCAL_RETURN_IF_ERROR(
      ReadInputText(path, kMaxConditionsFileBytes, "a calibration file", &text).WithContext(path));
  return ParseCalibration(text, path, record);
}

Status GyroscopeBaselineCalibration(const GyroscopeCalibrationSection& section,
                                    GyroscopeParameters* parameters, GyroscopeOffset* offset,
                                    Eigen::MatrixXd* covariance, GyroscopeOutputUnit* unit,
                                    bool* from_baseline) {
  *from_baseline = !EffectTermNames(section).empty();
  if (!*from_baseline) return GyroscopeCalibration(section, parameters, offset, covariance, unit);
  if (!section.baseline.present()) {
    return Status::Error(
        "the gyroscope section carries effect terms and no 12-unknown baseline "
        "to write in a format that holds the 12 only");
  }
  GyroscopeCalibrationSection baseline = section;
  baseline.parameter_order = section.baseline.parameter_order;
  baseline.values = section.baseline.values;
  baseline.covariance = section.baseline.covariance;
  return GyroscopeCalibration(baseline, parameters, offset, covariance, unit);
}

Status GyroscopeCalibrationModelOf(const GyroscopeCalibrationSection& section,
                                   GyroscopeCalibrationModel* model) {
  *model = GyroscopeCalibrationModel();
  ACCELCAL_RETURN_IF_ERROR(ParseGyroscopeOutputUnit(section.output_unit, &model->unit)
                               .WithContext("gyroscope/output_unit"));
  const size_t n = section.parameter_order.size();
  if (n < kGyroscopeCalibrationParameterCount || section.values.size() != static_cast<int>(n) ||
      section.covariance.rows() != static_cast<int>(n) ||
      section.covariance.cols() != static_cast<int>(n)) {
    return Status::Error(
        "the gyroscope section does not hold its 12 parameters, its effect terms and their "
        "covariance");
  }
  for (int p = 0; p < kGyroscopeParameterCount; ++p) model->parameters[p] = section.values[p];
  for (int k = 0; k < 3; ++k) model->offset[k] = section.values[kGyroscopeCalibrationOffsetX + k];
  std::vector<int> place(n, -1);
  for (int p = 0; p < kGyroscopeCalibrationParameterCount; ++p) place[p] = p;
  for (size_t i = kGyroscopeCalibrationParameterCount; i < n; ++i) {
    const int c = GyroscopeEffectCoefficientIndex(section.parameter_order[i]);
    if (c < 0) {
      return Status::Error("gyroscope/" + section.parameter_order[i] +
                           " is not an effect term this accelcal knows");
    }
    if (!GyroscopeEffectAppliedInUse(c)) {
      model->effects_not_applied.push_back(c);
      continue;
    }
    model->effects[c] = section.values[i];
    model->effects_in_file.push_back(c);
    place[i] = kGyroscopeCalibrationParameterCount + c;
  }
  model->covariance =
      Eigen::MatrixXd::Zero(kGyroscopeCorrectionUnknowns, kGyroscopeCorrectionUnknowns);
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < n; ++j) {
      if (place[i] >= 0 && place[j] >= 0)
        model->covariance(place[i], place[j]) = section.covariance(i, j);
    }
  }
  return Status::Ok();
}

}  // namespace accelcal
