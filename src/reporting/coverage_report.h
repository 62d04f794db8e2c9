#ifndef ACCELCAL_REPORTING_COVERAGE_REPORT_H_
#define ACCELCAL_REPORTING_COVERAGE_REPORT_H_

// The coverage study as a table a person reads and JSON a program reads.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "studies/coverage_study.h"

namespace accelcal {

// What coverage prints and writes: the baseline study and the hidden-effect table.
struct CoverageReport {
  std::string scenario_name;
  uint64_t seed = 1;
  CoverageResult baseline;
  std::vector<EffectImpact> effects;  // empty when the table was not asked for
};

// CoverageTable, then EffectImpactText.
std::string CoverageText(const CoverageReport& report);
// CoverageJson of the baseline with "problem", "scenario", "seed" and "effects" added.
nlohmann::json CoverageReportJson(const CoverageReport& report);

std::string CoverageTable(const std::string& scenario_name, const CoverageResult& result);
std::string EffectImpactText(const std::vector<EffectImpact>& table);
nlohmann::json CoverageJson(const CoverageResult& result);
nlohmann::json EffectImpactJson(const std::vector<EffectImpact>& table);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_COVERAGE_REPORT_H_
