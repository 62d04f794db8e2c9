#include "io/scenario_json.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "common/format.h"
#include "common/landmark_checks.h"
#include "io/course_data.h"
#include "io/csv_reader.h"
#include "io/input_file.h"
#include "io/input_text.h"
#include "io/json_file.h"
#include "models/effects.h"
#include "simulation/disturbances.h"
#include "simulation/embedded_scenarios.h"

namespace accelcal {
namespace {

// Every bound a scenario must meet, in one place: a scenario file and --set are held to the
// same limits, after everything is read or applied. They keep the simulation finite and its
// memory bounded (a run of 1e8 samples holds about 5 GB), and each says its unit.
constexpr double kMaxTiltSamples = 1e8;
constexpr double kMaxRunSamples = 1e8;
constexpr double kMaxAngleRad = 1e3;
constexpr double kMaxPositionM = 1e9;
constexpr double kMaxVelocityMps = 1e5;
constexpr double kMaxAccelerationMps2 = 1e4;
constexpr double kGenericLargestDeviation = 1e6;

using nlohmann::json;

Status CheckKeys(const json& object, const std::vector<std::string>& allowed,
                 const std::string& where) {
  if (!object.is_object()) return Status::Error(where + " must be a JSON object");
  for (const auto& item : object.items()) {
    if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end()) {
      std::string list;
      for (const std::string& key : allowed) list += (list.empty() ? "" : ", ") + key;
      return Status::Error(where + ": unknown key \"" + item.key() + "\"; expected " + list);
    }
  }
  return Status::Ok();
}

Status ReadNumber(const json& object, const char* key, const std::string& where, double* value) {
  if (!object.contains(key)) return Status::Ok();  // keep the default
  const json& item = object.at(key);
  if (!item.is_number() || !std::isfinite(item.get<double>())) {
    return Status::Error(where + "." + key + " must be a finite number");
  }
  *value = item.get<double>();
  return Status::Ok();
}

Status ReadPair(const json& object, const char* key, const std::string& where, double* first,
                double* second) {
  if (!object.contains(key)) return Status::Ok();
  const json& item = object.at(key);
  if (!item.is_array() || item.size() != 2 || !item[0].is_number() || !item[1].is_number() ||
      !std::isfinite(item[0].get<double>()) || !std::isfinite(item[1].get<double>())) {
    return Status::Error(where + "." + key + " must be two finite numbers [x, y]");
  }
  *first = item[0].get<double>();
  *second = item[1].get<double>();
  return Status::Ok();
}

Status ReadAngles(const json& object, const char* key, const std::string& where,
                  std::vector<double>* angles) {
  if (!object.contains(key) || !object.at(key).is_array() || object.at(key).empty()) {
    return Status::Error(where + "." + key + " must be a non-empty array of angles in radians");
  }
  for (const json& item : object.at(key)) {
    if (!item.is_number() || !std::isfinite(item.get<double>())) {
      return Status::Error(where + "." + key + " must hold finite numbers (radians)");
    }
    angles->push_back(item.get<double>());
  }
  return Status::Ok();
}

// object[key], a number (one name) or an array [x, y] (two), into the named settings.
Status ReadInto(const json& object, const char* key, const std::string& where,
                const std::vector<const char*>& names, Disturbances* disturbances) {
  if (!object.contains(key)) return Status::Ok();
  double values[2];
  ACCELCAL_RETURN_IF_ERROR(names.size() == 1
                               ? ReadNumber(object, key, where, &values[0])
                               : ReadPair(object, key, where, &values[0], &values[1]));
  for (size_t i = 0; i < names.size(); ++i) {
    ACCELCAL_RETURN_IF_ERROR(SetDisturbance(names[i], values[i], disturbances));
  }
  return Status::Ok();
}

Status RequireKeys(const json& object, const std::vector<const char*>& keys,
                   const std::string& where) {
  for (const char* key : keys) {
    if (!object.contains(key)) return Status::Error(where + " needs \"" + key + "\"");
  }
  return Status::Ok();
}

// object[key], when there, as {"at", "size": [x, y]} into the settings key_at, key_x, key_y
// (bias_step, position_offset: a place in the test and a size per axis).
Status ReadAtAndSize(const json& object, const std::string& key, const std::string& where,
                     Disturbances* disturbances) {
  if (!object.contains(key)) return Status::Ok();
  const json& value = object.at(key);
  const std::string value_where = where + "." + key;
  const std::string at = key + "_at", x = key + "_x", y = key + "_y";
  ACCELCAL_RETURN_IF_ERROR(CheckKeys(value, {"at", "size"}, value_where));
  ACCELCAL_RETURN_IF_ERROR(RequireKeys(value, {"at", "size"}, value_where));
  ACCELCAL_RETURN_IF_ERROR(ReadInto(value, "at", value_where, {at.c_str()}, disturbances));
  return ReadInto(value, "size", value_where, {x.c_str(), y.c_str()}, disturbances);
}

// The "disturbances" object of a scenario: the keys noise_ar1 [x, y], noise_student_t_dof,
// outlier_fraction, outlier_sigma, theta_harmonic {"order", "amplitude": [x, y], "phase"},
// bias_step {"at", "size": [x, y]}, scale_cubic [x, y], bias_warmup [x, y], bias_hysteresis
// [x, y], position_offset {"at", "size": [x, y]} and full_scale [x, y], each into its --set
// names (simulation/disturbances.h). An unknown key is an error; ranges are
// ValidateDisturbances's.
Status ParseDisturbances(const json& object, Disturbances* disturbances) {
  const std::string where = "disturbances";
  ACCELCAL_RETURN_IF_ERROR(
      CheckKeys(object,
                {"noise_ar1", "noise_student_t_dof", "outlier_fraction", "outlier_sigma",
                 "theta_harmonic", "bias_step", "scale_cubic", "bias_warmup", "bias_hysteresis",
                 "position_offset", "full_scale"},
                where));
  Disturbances parsed = *disturbances;
  ACCELCAL_RETURN_IF_ERROR(
      ReadInto(object, "noise_ar1", where, {"noise_ar1_x", "noise_ar1_y"}, &parsed));
  ACCELCAL_RETURN_IF_ERROR(
      ReadInto(object, "noise_student_t_dof", where, {"noise_student_t_dof"}, &parsed));
  ACCELCAL_RETURN_IF_ERROR(
      ReadInto(object, "outlier_fraction", where, {"outlier_fraction"}, &parsed));
  ACCELCAL_RETURN_IF_ERROR(ReadInto(object, "outlier_sigma", where, {"outlier_sigma"}, &parsed));
  if (object.contains("theta_harmonic")) {
    const json& harmonic = object.at("theta_harmonic");
    const std::string harmonic_where = where + ".theta_harmonic";
    ACCELCAL_RETURN_IF_ERROR(CheckKeys(harmonic, {"order", "amplitude", "phase"}, harmonic_where));
    ACCELCAL_RETURN_IF_ERROR(RequireKeys(harmonic, {"order", "amplitude"}, harmonic_where));
    ACCELCAL_RETURN_IF_ERROR(
        ReadInto(harmonic, "order", harmonic_where, {"theta_harmonic_order"}, &parsed));
    ACCELCAL_RETURN_IF_ERROR(ReadInto(harmonic, "amplitude", harmonic_where,
                                      {"theta_harmonic_x", "theta_harmonic_y"}, &parsed));
    ACCELCAL_RETURN_IF_ERROR(
        ReadInto(harmonic, "phase", harmonic_where, {"theta_harmonic_phase"}, &parsed));
  }
  ACCELCAL_RETURN_IF_ERROR(ReadAtAndSize(object, "bias_step", where, &parsed));
  ACCELCAL_RETURN_IF_ERROR(
      ReadInto(object, "scale_cubic", where, {"scale_cubic_x", "scale_cubic_y"}, &parsed));
  ACCELCAL_RETURN_IF_ERROR(
      ReadInto(object, "bias_warmup", where, {"bias_warmup_x", "bias_warmup_y"}, &parsed));
  ACCELCAL_RETURN_IF_ERROR(ReadInto(object, "bias_hysteresis", where,
                                    {"bias_hysteresis_x", "bias_hysteresis_y"}, &parsed));
  ACCELCAL_RETURN_IF_ERROR(ReadAtAndSize(object, "position_offset", where, &parsed));
  ACCELCAL_RETURN_IF_ERROR(
      ReadInto(object, "full_scale", where, {"full_scale_x", "full_scale_y"}, &parsed));
  *disturbances = parsed;
  return Status::Ok();
}

Status ParseTilt(const json& tilt, TiltSchedule* schedule) {
  ACCELCAL_RETURN_IF_ERROR(CheckKeys(
      tilt, {"schedule", "samples", "from_rad", "to_rad", "positions_rad", "angles_rad"}, "tilt"));
  const std::string kind = tilt.value("schedule", std::string("uniform"));
  double samples = schedule->sample_count;
  ACCELCAL_RETURN_IF_ERROR(ReadNumber(tilt, "samples", "tilt", &samples));
  if (kind != "list" &&
      (samples < 3 || samples > kMaxTiltSamples || samples != std::floor(samples))) {
    return Status::Error(
        StringPrintf("tilt.samples must be a whole number from 3 to %.0e", kMaxTiltSamples));
  }
  schedule->sample_count = static_cast<int>(samples);
  if (kind == "uniform") {
    schedule->kind = TiltSchedule::Kind::kUniform;
    ACCELCAL_RETURN_IF_ERROR(ReadNumber(tilt, "from_rad", "tilt", &schedule->theta_begin_rad));
    ACCELCAL_RETURN_IF_ERROR(ReadNumber(tilt, "to_rad", "tilt", &schedule->theta_end_rad));
  } else if (kind == "static") {
    schedule->kind = TiltSchedule::Kind::kStaticPositions;
    ACCELCAL_RETURN_IF_ERROR(ReadAngles(tilt, "positions_rad", "tilt", &schedule->positions_rad));
  } else if (kind == "list") {
    schedule->kind = TiltSchedule::Kind::kList;
    ACCELCAL_RETURN_IF_ERROR(ReadAngles(tilt, "angles_rad", "tilt", &schedule->angles_rad));
    schedule->sample_count = static_cast<int>(schedule->angles_rad.size());
  } else {
    return Status::Error("tilt.schedule is \"" + kind + "\"; expected uniform, static or list");
  }
  return Status::Ok();
}

Status ParseRun(const json& run, const std::string& base_dir, RunProfile* profile) {
  ACCELCAL_RETURN_IF_ERROR(CheckKeys(run, {"dt", "duration", "profile"}, "run"));
  ACCELCAL_RETURN_IF_ERROR(ReadNumber(run, "dt", "run", &profile->dt_s));
  ACCELCAL_RETURN_IF_ERROR(ReadNumber(run, "duration", "run", &profile->duration_s));
  if (!(profile->dt_s > 0.0) || !(profile->duration_s >= 2 * profile->dt_s) ||
      profile->duration_s / profile->dt_s > 1e8) {
    return Status::Error("run.dt must be positive and run.duration between 2 dt and 1e8 dt");
  }
  if (!run.contains("profile")) return Status::Error("run.profile is missing");
  const json& shape = run.at("profile");
  ACCELCAL_RETURN_IF_ERROR(CheckKeys(shape, {"segments", "smoothing", "csv"}, "run.profile"));
  const int count = static_cast<int>(std::llround(profile->duration_s / profile->dt_s));
  if (shape.contains("csv")) {
    if (!shape.at("csv").is_string()) return Status::Error("run.profile.csv must be a file name");
    std::string path = shape.at("csv").get<std::string>();
    if (!path.empty() && path[0] != '/') path = base_dir + "/" + path;
    CsvTable table;
    ACCELCAL_RETURN_IF_ERROR(ReadCsvFile(path, {{"t"}, {"ax"}, {"ay"}}, &table).WithContext(path));
    if (table.row_count != count) {
      return Status::Error(path + ": " + std::to_string(table.row_count) +
                           " rows, but the run has " + std::to_string(count) +
                           " samples (duration / dt)");
    }
    for (int j = 0; j < count; ++j) {
      if (std::abs(table.numbers[0][j] - j * profile->dt_s) > 1e-6 * profile->dt_s + 1e-12) {
        return Status::Error(path + ": row " + std::to_string(j + 1) +
                             " has t = " + StringPrintf("%g", table.numbers[0][j]) +
                             " s, expected " + StringPrintf("%g", j * profile->dt_s));
      }
    }
    profile->csv_acceleration_x = table.numbers[1];
    profile->csv_acceleration_y = table.numbers[2];
    return Status::Ok();
  }
  ACCELCAL_RETURN_IF_ERROR(ReadNumber(shape, "smoothing", "run.profile", &profile->smoothing_s));
  if (profile->smoothing_s < 0.0) return Status::Error("run.profile.smoothing must be >= 0 (s)");
  if (!shape.contains("segments") || !shape.at("segments").is_array() ||
      shape.at("segments").empty()) {
    return Status::Error("run.profile needs \"segments\" (or \"csv\")");
  }
  double covered = 0.0;
  for (const json& item : shape.at("segments")) {
    ACCELCAL_RETURN_IF_ERROR(
        CheckKeys(item, {"duration", "acceleration"}, "run.profile.segments[]"));
    AccelerationSegment segment;
    ACCELCAL_RETURN_IF_ERROR(ReadNumber(item, "duration", "segment", &segment.duration_s));
    ACCELCAL_RETURN_IF_ERROR(ReadPair(item, "acceleration", "segment", &segment.acceleration_x,
                                      &segment.acceleration_y));
    if (!(segment.duration_s > 0.0))
      return Status::Error("every segment needs a positive duration (s)");
    covered += segment.duration_s;
    profile->segments.push_back(segment);
  }
  if (covered < profile->duration_s - 1e-9) {
    return Status::Error(StringPrintf("run.profile.segments cover %g s of a %g s run", covered,
                                      profile->duration_s));
  }
  return Status::Ok();
}

Status ParseLandmarks(const json& landmarks, LandmarkSpec* spec) {
  ACCELCAL_RETURN_IF_ERROR(CheckKeys(landmarks, {"listed", "decoys"}, "landmarks"));
  if (landmarks.contains("listed") == landmarks.contains("decoys")) {
    return Status::Error("landmarks needs exactly one of \"listed\" and \"decoys\"");
  }
  if (landmarks.contains("decoys")) {
    const json& decoys = landmarks.at("decoys");
    ACCELCAL_RETURN_IF_ERROR(CheckKeys(decoys, {"count", "min_distance"}, "landmarks.decoys"));
    double count = spec->decoy_count;
    ACCELCAL_RETURN_IF_ERROR(ReadNumber(decoys, "count", "landmarks.decoys", &count));
    ACCELCAL_RETURN_IF_ERROR(
        ReadNumber(decoys, "min_distance", "landmarks.decoys", &spec->decoy_min_distance_m));
    if (count < 1 || count > 25 || count != std::floor(count) ||
        !(spec->decoy_min_distance_m > 0.0)) {
      return Status::Error(
          "landmarks.decoys needs a count from 1 to 25 and a positive min_distance (m)");
    }
    spec->decoys = true;
    spec->decoy_count = static_cast<int>(count);
    return Status::Ok();
  }
  const json& listed = landmarks.at("listed");
  if (!listed.is_array() || listed.empty())
    return Status::Error("landmarks.listed must be a non-empty array");
  for (const json& item : listed) {
    ACCELCAL_RETURN_IF_ERROR(CheckKeys(item, {"name", "position"}, "landmarks.listed[]"));
    Landmark landmark;
    if (!item.contains("name") || !item.at("name").is_string() ||
        item.at("name").get<std::string>().empty()) {
      return Status::Error("every listed landmark needs a name");
    }
    landmark.name = item.at("name").get<std::string>();
    // Names appear in every table and message: printable and short, as in landmarks.csv.
    if (landmark.name.size() > 100 || !IsPrintableUtf8(landmark.name)) {
      return Status::Error("landmark name '" + EchoInput(landmark.name) +
                           "' must be at most 100 printable characters");
    }
    if (!item.contains("position"))
      return Status::Error("landmark " + landmark.name + " needs a position");
    ACCELCAL_RETURN_IF_ERROR(
        ReadPair(item, "position", "landmark " + landmark.name, &landmark.x_m, &landmark.y_m));
    spec->listed.push_back(landmark);
  }
  return CheckLandmarks(spec->listed).WithContext("landmarks.listed");
}

Status SetParameter(const std::string& name, double value, SimulationTruth* truth) {
  const ParameterInfo* info = FindParameter(name);
  if (info == nullptr) return Status::Error("'" + name + "' is not a parameter of the spec");
  if (!std::isfinite(value)) return Status::Error(name + " must be finite");
  if (IsNoiseRatio(info->parameter) && !(value > 0.0)) {
    return Status::Error(name + " (a variance ratio) must be positive");
  }
  truth->parameters[info->parameter] = value;
  return Status::Ok();
}

Status CheckRange(const std::string& name, double value, double low, double high,
                  const char* unit) {
  if (std::isfinite(value) && value >= low && value <= high) return Status::Ok();
  return Status::Error(
      StringPrintf("%s = %.6g is outside [%.6g, %.6g] %s", name.c_str(), value, low, high, unit));
}

Status ValidateScenario(const Scenario& scenario) {
  const SimulationTruth& truth = scenario.truth;
  ACCELCAL_RETURN_IF_ERROR(CheckRange("gravity", truth.gravity_mps2, 1.0, 100.0, "m/s^2"));
  ACCELCAL_RETURN_IF_ERROR(CheckRange("noise_variance_x_stated", truth.stated_noise_variance_x,
                                      1e-12, 1e4, "(m/s^2)^2"));
  ACCELCAL_RETURN_IF_ERROR(CheckRange("noise_variance_y_stated", truth.stated_noise_variance_y,
                                      1e-12, 1e4, "(m/s^2)^2"));
  for (const double value : {scenario.initial_position_x_m, scenario.initial_position_y_m}) {
    ACCELCAL_RETURN_IF_ERROR(
        CheckRange("initial_position", value, -kMaxPositionM, kMaxPositionM, "m"));
  }
  for (const double value : {scenario.initial_velocity_x_mps, scenario.initial_velocity_y_mps}) {
    ACCELCAL_RETURN_IF_ERROR(
        CheckRange("initial_velocity", value, -kMaxVelocityMps, kMaxVelocityMps, "m/s"));
  }
  const TiltSchedule& tilt = scenario.tilt;
  const double tilt_samples = tilt.kind == TiltSchedule::Kind::kList
                                  ? static_cast<double>(tilt.angles_rad.size())
                                  : static_cast<double>(tilt.sample_count);
  ACCELCAL_RETURN_IF_ERROR(CheckRange("tilt_samples", tilt_samples, 3, kMaxTiltSamples, "samples"));
  for (const double angle : {tilt.theta_begin_rad, tilt.theta_end_rad}) {
    ACCELCAL_RETURN_IF_ERROR(CheckRange("tilt angle", angle, -kMaxAngleRad, kMaxAngleRad, "rad"));
  }
  for (const std::vector<double>* angles : {&tilt.positions_rad, &tilt.angles_rad}) {
    for (const double angle : *angles) {
      ACCELCAL_RETURN_IF_ERROR(CheckRange("tilt angle", angle, -kMaxAngleRad, kMaxAngleRad, "rad"));
    }
  }
  const RunProfile& run = scenario.run;
  ACCELCAL_RETURN_IF_ERROR(CheckRange("run_dt", run.dt_s, kMinRunStepS, kMaxRunStepS, "s"));
  ACCELCAL_RETURN_IF_ERROR(CheckRange("run_duration", run.duration_s, 0.0, 1e7, "s"));
  // The run has llround(duration / dt) samples t_j = j dt; integrating needs two.
  const double run_samples = std::round(run.duration_s / run.dt_s);
  if (!(run_samples >= 2 && run_samples <= kMaxRunSamples)) {
    return Status::Error(StringPrintf(
        "run_duration / run_dt = %.6g s / %.6g s gives %.6g samples; a run needs 2 to %.0e",
        run.duration_s, run.dt_s, run_samples, kMaxRunSamples));
  }
  for (const AccelerationSegment& segment : run.segments) {
    ACCELCAL_RETURN_IF_ERROR(CheckRange("segment acceleration", segment.acceleration_x,
                                        -kMaxAccelerationMps2, kMaxAccelerationMps2, "m/s^2"));
    ACCELCAL_RETURN_IF_ERROR(CheckRange("segment acceleration", segment.acceleration_y,
                                        -kMaxAccelerationMps2, kMaxAccelerationMps2, "m/s^2"));
  }
  for (const std::vector<double>* values : {&run.csv_acceleration_x, &run.csv_acceleration_y}) {
    for (const double value : *values) {
      ACCELCAL_RETURN_IF_ERROR(CheckRange("profile acceleration", value, -kMaxAccelerationMps2,
                                          kMaxAccelerationMps2, "m/s^2"));
    }
  }
  for (const Landmark& landmark : scenario.landmarks.listed) {
    for (const double value : {landmark.x_m, landmark.y_m}) {
      ACCELCAL_RETURN_IF_ERROR(
          CheckRange("landmark " + landmark.name, value, -kMaxPositionM, kMaxPositionM, "m"));
    }
  }
  for (const ParameterInfo& info : ParameterCatalogue()) {
    const double largest = info.effect->largest_deviation > 0.0 ? info.effect->largest_deviation
                                                                : kGenericLargestDeviation;
    const double value = truth.parameters[info.parameter];
    ACCELCAL_RETURN_IF_ERROR(
        CheckRange(info.name, value, info.neutral - largest, info.neutral + largest, info.unit));
  }
  return ValidateDisturbances(truth.disturbances);
}

}  // namespace

Status ParseScenario(const std::string& json_text, const std::string& base_dir,
                     Scenario* scenario) {
  json document;
  ACCELCAL_RETURN_IF_ERROR(ParseJsonStrict(json_text, &document));
  ACCELCAL_RETURN_IF_ERROR(
      CheckKeys(document,
                {"name", "description", "gravity", "noise_variance", "initial_position",
                 "initial_velocity", "tilt", "run", "landmarks", "truth", "disturbances"},
                "scenario"));
  Scenario parsed;
  parsed.name = document.value("name", std::string("unnamed"));
  parsed.description = document.value("description", std::string());
  SimulationTruth& truth = parsed.truth;
  ACCELCAL_RETURN_IF_ERROR(ReadNumber(document, "gravity", "scenario", &truth.gravity_mps2));
  ACCELCAL_RETURN_IF_ERROR(ReadPair(document, "noise_variance", "scenario",
                                    &truth.stated_noise_variance_x,
                                    &truth.stated_noise_variance_y));
  if (!(truth.gravity_mps2 > 0.0) || !(truth.stated_noise_variance_x > 0.0) ||
      !(truth.stated_noise_variance_y > 0.0)) {
    return Status::Error("gravity and noise_variance must be positive");
  }
  ACCELCAL_RETURN_IF_ERROR(ReadPair(document, "initial_position", "scenario",
                                    &parsed.initial_position_x_m, &parsed.initial_position_y_m));
  ACCELCAL_RETURN_IF_ERROR(ReadPair(document, "initial_velocity", "scenario",
                                    &parsed.initial_velocity_x_mps,
                                    &parsed.initial_velocity_y_mps));
  if (document.contains("tilt"))
    ACCELCAL_RETURN_IF_ERROR(ParseTilt(document.at("tilt"), &parsed.tilt));
  if (!document.contains("run")) return Status::Error("scenario.run is missing");
  ACCELCAL_RETURN_IF_ERROR(ParseRun(document.at("run"), base_dir, &parsed.run));
  if (!document.contains("landmarks")) return Status::Error("scenario.landmarks is missing");
  ACCELCAL_RETURN_IF_ERROR(ParseLandmarks(document.at("landmarks"), &parsed.landmarks));
  if (document.contains("truth")) {
    const json& values = document.at("truth");
    if (!values.is_object())
      return Status::Error("scenario.truth must be an object of name: value");
    for (const auto& item : values.items()) {
      if (!item.value().is_number())
        return Status::Error("truth." + item.key() + " must be a number");
      ACCELCAL_RETURN_IF_ERROR(
          SetParameter(item.key(), item.value().get<double>(), &truth).WithContext("truth"));
    }
  }
  if (document.contains("disturbances")) {
    ACCELCAL_RETURN_IF_ERROR(ParseDisturbances(document.at("disturbances"), &truth.disturbances));
  }
  ACCELCAL_RETURN_IF_ERROR(ValidateScenario(parsed));
  *scenario = parsed;
  return Status::Ok();
}

Status LoadScenario(const std::string& path, Scenario* scenario) {
  std::string text;
  ACCELCAL_RETURN_IF_ERROR(
      ReadInputText(path, kMaxConditionsFileBytes, "a scenario JSON file", &text)
          .WithContext(path));
  const size_t slash = path.find_last_of('/');
  const std::string base_dir = slash == std::string::npos ? "." : path.substr(0, slash);
  return ParseScenario(text, base_dir, scenario).WithContext(path);
}

Status ApplyScenarioOverrides(const std::string& assignments, Scenario* scenario) {
  std::istringstream stream(assignments);
  std::string assignment;
  while (std::getline(stream, assignment, ',')) {
    if (assignment.empty()) continue;
    const size_t equals = assignment.find('=');
    double value;
    if (equals == std::string::npos || !ParseFiniteNumber(assignment.substr(equals + 1), &value)) {
      return Status::Error("'" + assignment + "' is not name=number");
    }
    const std::string name = assignment.substr(0, equals);
    SimulationTruth& truth = scenario->truth;
    if (name == "gravity" || name == "noise_variance_x_stated" ||
        name == "noise_variance_y_stated" || name == "run_dt" || name == "run_duration") {
      if (!(value > 0.0)) return Status::Error(name + " must be positive");
      if (name == "gravity") truth.gravity_mps2 = value;
      if (name == "noise_variance_x_stated") truth.stated_noise_variance_x = value;
      if (name == "noise_variance_y_stated") truth.stated_noise_variance_y = value;
      if (name == "run_dt") scenario->run.dt_s = value;
      if (name == "run_duration") scenario->run.duration_s = value;
    } else if (name == "tilt_samples") {
      if (value < 3 || value > kMaxTiltSamples || value != std::floor(value) ||
          scenario->tilt.kind == TiltSchedule::Kind::kList) {
        return Status::Error(StringPrintf(
            "tilt_samples must be a whole number from 3 to %.0e (and the schedule not a list)",
            kMaxTiltSamples));
      }
      scenario->tilt.sample_count = static_cast<int>(value);
    } else if (FindParameter(name) != nullptr) {
      ACCELCAL_RETURN_IF_ERROR(SetParameter(name, value, &truth));
    } else if (IsDisturbanceName(name)) {
      // Ranges are checked with the rest of the scenario below.
      ACCELCAL_RETURN_IF_ERROR(SetDisturbance(name, value, &truth.disturbances));
    } else {
      std::string names;
      for (const ParameterInfo& info : ParameterCatalogue())
        names += std::string(names.empty() ? "" : ", ") + info.name;
      std::string disturbances;
      for (const std::string& disturbance : DisturbanceNames())
        disturbances += std::string(disturbances.empty() ? "" : ", ") + disturbance;
      return Status::Error(
          "'" + name + "' is neither a parameter (" + names +
          "), a setting (gravity, noise_variance_x_stated, noise_variance_y_stated, "
          "tilt_samples, run_duration, run_dt) nor a disturbance (" +
          disturbances + ")");
    }
  }
  const RunProfile& run = scenario->run;
  double covered = 0.0;
  for (const AccelerationSegment& segment : run.segments) covered += segment.duration_s;
  if (!run.segments.empty() && covered < run.duration_s - 1e-9) {
    return Status::Error(
        StringPrintf("the profile's segments cover %g s of the %g s run", covered, run.duration_s));
  }
  if (!run.csv_acceleration_x.empty() &&
      std::llround(run.duration_s / run.dt_s) !=
          static_cast<long long>(run.csv_acceleration_x.size())) {
    return Status::Error("run_duration and run_dt cannot change a run given as a CSV profile");
  }
  return ValidateScenario(*scenario);
}

Status LoadDefaultScenario(Scenario* scenario) {
  return ParseScenario(DefaultScenarioJson(), ".", scenario)
      .WithContext("embedded scenario tp2-2018");
}

Status LoadScenarioOrDefault(const std::string& path, const std::string& assignments,
                             Scenario* scenario) {
  ACCELCAL_RETURN_IF_ERROR(path.empty() ? LoadDefaultScenario(scenario)
                                        : LoadScenario(path, scenario));
  return ApplyScenarioOverrides(assignments, scenario).WithContext("--set");
}

Status DescribeSimulation(const Scenario& scenario, const std::string& scenario_file, uint64_t seed,
                          DataSource* source) {
  DataSource described;
  described.simulated = true;
  described.scenario = scenario.name;
  described.seed = seed;
  if (!scenario_file.empty()) {
    ACCELCAL_RETURN_IF_ERROR(HashInputFile(scenario_file, &described.files["scenario"]));
  }
  for (const ParameterInfo& info : ParameterCatalogue()) {
    const double value = scenario.truth.parameters[info.parameter];
    if (!info.baseline && value != info.neutral) described.hidden.emplace_back(info.name, value);
  }
  const nlohmann::json disturbances = DisturbancesJson(scenario.truth.disturbances);
  const nlohmann::json defaults = DisturbancesJson(Disturbances());
  for (const std::string& name : DisturbanceNames()) {
    if (scenario.truth.disturbances.any() && disturbances.contains(name) &&
        disturbances[name].is_number() && disturbances[name] != defaults[name]) {
      described.hidden.emplace_back(name, disturbances[name].get<double>());
    }
  }
  *source = std::move(described);
  return Status::Ok();
}

}  // namespace accelcal
