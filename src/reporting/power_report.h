#ifndef ACCELCAL_REPORTING_POWER_REPORT_H_
#define ACCELCAL_REPORTING_POWER_REPORT_H_

// What power prints and writes: per effect of the catalogue, its sigma on the scenario and
// how often discovery named it when hidden at each size, with the Monte Carlo sd of such a
// rate; and the same rows as JSON.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "studies/power_study.h"

namespace accelcal {

struct PowerReport {
  std::string scenario_name;
  PowerOptions options;  // the sizes, trials and alpha the study ran with
  std::vector<PowerRow> rows;
};

std::string PowerText(const PowerReport& report);

// {"problem": "power", "scenario", "seed", "trials", "alpha", "rows": [{"name", "sigma",
// "unit", "sizes_sigma", "detection", "other_effects_named"}, ...], "units"} (docs/json.md).
nlohmann::json PowerJson(const PowerReport& report);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_POWER_REPORT_H_
