#ifndef ACCELCAL_REPORTING_MIN_SAMPLES_REPORT_H_
#define ACCELCAL_REPORTING_MIN_SAMPLES_REPORT_H_

// "How many samples" for a person and for a program: min_samples' screen (each design's
// N_min, its curve near N_min, the Monte Carlo checks, and why the report's per-axis N is
// so large) and the JSON that min_samples and analyze both write.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "studies/min_samples.h"

namespace accelcal {

struct MinSamplesReport {
  MinSamplesResult study;
  std::vector<Landmark> landmarks;
  double max_error = 0.01;
};

std::string MinSamplesText(const MinSamplesReport& report);

// {"problem", "truth" (the decided landmark or null), "max_error", "full_samples",
// "designs": DesignJson of each with its checks}.
nlohmann::json MinSamplesJson(const MinSamplesReport& report);

nlohmann::json DesignJson(const DesignCurve& design, const std::vector<MonteCarloCheck>& checks);

// N_min (or N_min_3sigma) for a person: the number, or "none up to N = <limit>" when no
// number of samples up to `limit` (the search's upper end) meets the criterion.
std::string SampleCountText(int n_min, int limit);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_MIN_SAMPLES_REPORT_H_
