#ifndef ACCELCAL_REPORTING_MIN_SAMPLES_REPORT_H_
#define ACCELCAL_REPORTING_MIN_SAMPLES_REPORT_H_

// One design's answer to "how many samples" as JSON (name, N_min, N_min_3sigma, the
// curve), shared by min_samples and analyze so both write the same thing.

#include <nlohmann/json.hpp>

#include "studies/min_samples.h"

namespace accelcal {

nlohmann::json DesignJson(const DesignCurve& design, const nlohmann::json& monte_carlo_checks);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_MIN_SAMPLES_REPORT_H_
