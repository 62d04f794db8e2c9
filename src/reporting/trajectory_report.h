#ifndef ACCELCAL_REPORTING_TRAJECTORY_REPORT_H_
#define ACCELCAL_REPORTING_TRAJECTORY_REPORT_H_

// What the trajectory binary prints and writes: the decision first, then the endpoint
// with both covariance parts, the landmark table, and the reference report's bound
// beside the correct terms, with the explanation derived from those numbers. Also the
// path series as CSV for tools/plot_trajectory.py.

#include <array>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "estimation/tilt_table/baseline_parameters.h"
#include "estimation/tilt_table/error_budget.h"
#include "estimation/tilt_table/landmark_decision.h"
#include "estimation/tilt_table/trajectory.h"

namespace accelcal {

struct TrajectoryReport {
  BaselineFit fit;
  RunConditions conditions;
  DeadReckoningResult trajectory;
  LandmarkDecision decision;
  std::array<AxisErrorBudget, 2> budget;
  std::map<std::string, std::string> input_files;
};

std::string TrajectoryTable(const TrajectoryReport& report);
nlohmann::json TrajectoryJson(const TrajectoryReport& report);
// t_s, corrected and raw positions, total/parameter/noise covariance at every kept sample.
std::string TrajectoryPathCsv(const DeadReckoningResult& trajectory);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_TRAJECTORY_REPORT_H_
