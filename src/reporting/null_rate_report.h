#ifndef ACCELCAL_REPORTING_NULL_RATE_REPORT_H_
#define ACCELCAL_REPORTING_NULL_RATE_REPORT_H_

// What null_rate prints and writes: a header saying where the null data came from (the
// scenario, the designs' tilt tests, the command that reproduces the run), the table of
// cells, the pooled rate per alpha against its bound and what the false discoveries
// claimed; and the same numbers as JSON.

#include <nlohmann/json.hpp>
#include <string>

#include "studies/null_rate_study.h"

namespace accelcal {

struct NullRateReport {
  NullRateOptions options;  // what the study ran (designs already checked)
  Scenario course;          // the scenario the null designs were built from (studies/)
  NullRateResult study;
};

std::string NullRateText(const NullRateReport& report);

// {"problem", "data", "scenario", "seed", "command", "designs" (name, tilt), "noise_factors",
// "alphas", "datasets_per_cell", "cells", "pooled", "seconds", "threads"}.
nlohmann::json NullRateJson(const NullRateReport& report);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_NULL_RATE_REPORT_H_
