// Prints the catalogue's units as JSON, {"bias_x": "m/s^2", ...}: what every `units` map of
// the binaries' JSON must agree with (tests/json_schema_test.py, docs/json.md).

#include <iostream>
#include <nlohmann/json.hpp>

#include "models/effects.h"

int main() {
  nlohmann::json units = nlohmann::json::object();
  for (const accelcal::ParameterInfo& info : accelcal::ParameterCatalogue()) {
    units[info.name] = info.unit;
  }
  std::cout << units.dump() << "\n";
  return 0;
}
