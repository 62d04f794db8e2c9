#include "io/run_conditions.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>

#include "common/format.h"
#include "io/datos_txt.h"
#include "io/input_file.h"
#include "io/input_text.h"
#include "io/json_file.h"

namespace accelcal {
namespace {

using nlohmann::json;

Status ReadPair(const json& document, const char* key, double* first, double* second) {
  if (!document.contains(key)) return Status::Error(std::string("missing \"") + key + "\"");
  const json& value = document.at(key);
  if (!value.is_array() || value.size() != 2 || !value[0].is_number() || !value[1].is_number()) {
    return Status::Error(std::string("\"") + key + "\" must be an array of two numbers [x, y]");
  }
  *first = value[0].get<double>();
  *second = value[1].get<double>();
  if (!std::isfinite(*first) || !std::isfinite(*second)) {
    return Status::Error(std::string("\"") + key + "\" must be finite");
  }
  return Status::Ok();
}

}  // namespace

Status ParseScenarioJson(const std::string& text, RunConditions* conditions) {
  json document;
  ACCELCAL_RETURN_IF_ERROR(ParseJsonStrict(text, &document));
  if (!document.is_object()) return Status::Error("expected a JSON object");
  for (const auto& item : document.items()) {
    const std::string& key = item.key();
    if (key != "initial_position" && key != "initial_velocity" && key != "noise_variance" &&
        key != "gravity") {
      return Status::Error("unknown key \"" + EchoInput(key) +
                           "\"; expected initial_position, initial_velocity, noise_variance, "
                           "gravity");
    }
  }
  RunConditions parsed;
  ACCELCAL_RETURN_IF_ERROR(ReadPair(document, "initial_position", &parsed.initial_position_x_m,
                                    &parsed.initial_position_y_m));
  ACCELCAL_RETURN_IF_ERROR(ReadPair(document, "initial_velocity", &parsed.initial_velocity_x_mps,
                                    &parsed.initial_velocity_y_mps));
  ACCELCAL_RETURN_IF_ERROR(
      ReadPair(document, "noise_variance", &parsed.noise_variance_x, &parsed.noise_variance_y));
  if (parsed.noise_variance_x <= 0.0 || parsed.noise_variance_y <= 0.0) {
    return Status::Error("\"noise_variance\" must be positive");
  }
  if (document.contains("gravity")) {
    const json& gravity = document.at("gravity");
    if (!gravity.is_number() || !(gravity.get<double>() > 0.0) ||
        !std::isfinite(gravity.get<double>())) {
      return Status::Error("\"gravity\" must be a positive number (m/s^2)");
    }
    parsed.has_gravity = true;
    parsed.gravity_mps2 = gravity.get<double>();
  }
  *conditions = parsed;
  return Status::Ok();
}

std::string ScenarioJson(const RunConditions& conditions) {
  json document = {
      {"initial_position", {conditions.initial_position_x_m, conditions.initial_position_y_m}},
      {"initial_velocity", {conditions.initial_velocity_x_mps, conditions.initial_velocity_y_mps}},
      {"noise_variance", {conditions.noise_variance_x, conditions.noise_variance_y}}};
  if (conditions.has_gravity) document["gravity"] = conditions.gravity_mps2;
  return document.dump(2) + "\n";
}

Status CheckRunConditions(const RunConditions& conditions) {
  auto within = [](const char* what, double value, double low, double high, const char* unit,
                   const char* hint) {
    if (std::isfinite(value) && value >= low && value <= high) return Status::Ok();
    return Status::Error(StringPrintf("the %s %.6g %s is outside [%.6g, %.6g]%s", what, value, unit,
                                      low, high, hint));
  };
  for (const double value : {conditions.initial_position_x_m, conditions.initial_position_y_m}) {
    ACCELCAL_RETURN_IF_ERROR(within("initial position", value, -1e9, 1e9, "m", ""));
  }
  for (const double value :
       {conditions.initial_velocity_x_mps, conditions.initial_velocity_y_mps}) {
    ACCELCAL_RETURN_IF_ERROR(within("initial velocity", value, -1e5, 1e5, "m/s", ""));
  }
  const char* variance_hint =
      "; is it a variance in (m/s^2)^2 (not a standard deviation, not "
      "in other units)?";
  ACCELCAL_RETURN_IF_ERROR(within("noise variance of x", conditions.noise_variance_x, 1e-12, 1e4,
                                  "(m/s^2)^2", variance_hint));
  ACCELCAL_RETURN_IF_ERROR(within("noise variance of y", conditions.noise_variance_y, 1e-12, 1e4,
                                  "(m/s^2)^2", variance_hint));
  if (conditions.has_gravity) {
    ACCELCAL_RETURN_IF_ERROR(within("gravity", conditions.gravity_mps2, 1.0, 100.0, "m/s^2", ""));
  }
  return Status::Ok();
}

Status LoadRunConditions(const std::string& path, RunConditions* conditions) {
  // By extension, in any case (".json", ".JSON").
  const std::string extension = ".json";
  const bool is_json =
      path.size() >= extension.size() &&
      std::equal(extension.begin(), extension.end(), path.end() - extension.size(),
                 [](char expected, char actual) {
                   return expected == std::tolower(static_cast<unsigned char>(actual));
                 });
  std::string text;
  Status status = ReadInputText(path, kMaxConditionsFileBytes,
                                is_json ? "a scenario JSON file" : "a datos.txt file", &text);
  if (status.ok()) {
    status = is_json ? ParseScenarioJson(text, conditions) : ParseDatosTxt(text, conditions);
  }
  if (status.ok()) status = CheckRunConditions(*conditions);
  return status.WithContext(path);
}

}  // namespace accelcal
