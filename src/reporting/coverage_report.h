#ifndef ACCELCAL_REPORTING_COVERAGE_REPORT_H_
#define ACCELCAL_REPORTING_COVERAGE_REPORT_H_

// The coverage study as a table a person reads and JSON a program reads.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "studies/coverage_study.h"

namespace accelcal {

std::string CoverageTable(const std::string& scenario_name, const CoverageResult& result);
std::string EffectImpactText(const std::vector<EffectImpact>& table);
nlohmann::json CoverageJson(const CoverageResult& result);
nlohmann::json EffectImpactJson(const std::vector<EffectImpact>& table);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_COVERAGE_REPORT_H_
