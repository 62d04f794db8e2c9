#ifndef ACCELCAL_REPORTING_MIN_SAMPLES_REPORT_H_
#define ACCELCAL_REPORTING_MIN_SAMPLES_REPORT_H_

// One design's answer to "how many samples" as JSON (name, N_min, N_min_3sigma, the
// curve), shared by min_samples and analyze so both write the same thing.

#include <nlohmann/json.hpp>
#include <string>

#include "studies/min_samples.h"

namespace accelcal {

nlohmann::json DesignJson(const DesignCurve& design, const nlohmann::json& monte_carlo_checks);

// N_min (or N_min_3sigma) for a person: the number, or "none up to N = <limit>" when no
// number of samples up to `limit` (the search's upper end) meets the criterion.
std::string SampleCountText(int n_min, int limit);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_MIN_SAMPLES_REPORT_H_
