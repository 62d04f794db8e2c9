#include "reporting/power_report.h"

#include <cmath>

#include "common/format.h"
#include "reporting/estimate_json.h"

namespace accelcal {

std::string PowerText(const PowerReport& report) {
  const PowerOptions& options = report.options;
  // clang-format off
  std::string text = StringPrintf(
      "accelcal power: how often discover names an effect hidden at k sigma (scenario %s, %d datasets per cell, alpha %g)\n\n"
      "  effect                 sigma (unit)              ",
      report.scenario_name.c_str(), options.trials, options.alpha);
  // clang-format on
  for (double size : options.sizes_sigma) text += StringPrintf("  %4.1f sigma", size);
  text += "\n";
  for (const PowerRow& row : report.rows) {
    const ParameterInfo& info = Info(row.effect);
    text += StringPrintf("  %-22s %.2e %-13s", info.name, row.sigma, info.unit);
    for (double rate : row.detection) text += StringPrintf("  %9.0f%%", 100 * rate);
    text += "\n";
  }
  text += StringPrintf(
      "  (Monte Carlo sd of a rate p from %d datasets: sqrt(p(1-p)/%d), at most %.0f%%)\n",
      options.trials, options.trials, 50.0 / std::sqrt(options.trials));
  return text;
}

nlohmann::json PowerJson(const PowerReport& report) {
  nlohmann::json rows = nlohmann::json::array();
  std::vector<std::string> names;
  for (const PowerRow& row : report.rows) {
    const ParameterInfo& info = Info(row.effect);
    names.push_back(info.name);
    rows.push_back({{"name", info.name},
                    {"sigma", row.sigma},
                    {"unit", info.unit},
                    {"sizes_sigma", report.options.sizes_sigma},
                    {"detection", row.detection},
                    {"other_effects_named", row.other_effects}});
  }
  // What the text's header says, too.
  return {{"problem", "power"},
          {"scenario", report.scenario_name},
          {"seed", report.options.seed},
          {"trials", report.options.trials},
          {"alpha", report.options.alpha},
          {"rows", rows},
          {"units", UnitsJson(names)}};
}

}  // namespace accelcal
