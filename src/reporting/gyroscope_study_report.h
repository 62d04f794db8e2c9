#ifndef ACCELCAL_REPORTING_GYROSCOPE_STUDY_REPORT_H_
#define ACCELCAL_REPORTING_GYROSCOPE_STUDY_REPORT_H_

// What gyroscope_study prints and writes: the design simulated, the verdict, then per gyroscope
// unknown the truth, the mean estimate, its bias in reported sigma, the Monte Carlo spread, the
// mean reported sigma, their ratio and the coverage at 1, 2, 3 sigma; the gyroscope fit
// statistic's mean chi2/dof and its p < 0.01 rate. For a design the calibration refuses: the
// refusal, the unknowns it leaves undetermined and the axes to turn about.

#include <nlohmann/json.hpp>
#include <string>

#include "studies/gyroscope_monte_carlo.h"

namespace accelcal {

struct GyroscopeStudyReport {
  GyroscopeMonteCarloOptions options;
  GyroscopeMonteCarloResult result;
};

std::string GyroscopeStudyText(const GyroscopeStudyReport& report);

// {"problem": "gyroscope_study", "design", "refused", "refusal", "undetermined",
// "turn_axes_to_add", "unknowns" (one object each), "fit_statistic", "verdict", "seconds"}.
nlohmann::json GyroscopeStudyJson(const GyroscopeStudyReport& report);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_GYROSCOPE_STUDY_REPORT_H_
