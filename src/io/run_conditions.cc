#include "io/run_conditions.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/datos_txt.h"

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
  try {
    document = json::parse(text);
  } catch (const json::parse_error& error) {
    return Status::Error(std::string("not valid JSON (") + error.what() + ")");
  }
  if (!document.is_object()) return Status::Error("expected a JSON object");
  for (const auto& item : document.items()) {
    const std::string& key = item.key();
    if (key != "initial_position" && key != "initial_velocity" && key != "noise_variance" &&
        key != "gravity") {
      return Status::Error("unknown key \"" + key +
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

Status LoadRunConditions(const std::string& path, RunConditions* conditions) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    return Status::Error("cannot open the file; check the path and permissions").WithContext(path);
  }
  std::ostringstream buffer;
  buffer << file.rdbuf();
  const bool is_json = path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0;
  const Status status = is_json ? ParseScenarioJson(buffer.str(), conditions)
                                : ParseDatosTxt(buffer.str(), conditions);
  return status.WithContext(path);
}

}  // namespace accelcal
