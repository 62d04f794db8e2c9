#ifndef ACCELCAL_REPORTING_JOINT_REPORT_H_
#define ACCELCAL_REPORTING_JOINT_REPORT_H_

// Linear and joint solutions side by side: every parameter +- 1 sigma in both, the shift
// between them in the linear sigma, chi-square per residual group, the endpoint with its
// landmark table under each, and the landmark hypotheses.

#include <nlohmann/json.hpp>
#include <string>

#include "estimation/tilt_table/baseline_parameters.h"
#include "estimation/tilt_table/joint_estimator.h"
#include "estimation/tilt_table/landmark_decision.h"
#include "estimation/tilt_table/trajectory.h"

namespace accelcal {

struct JointReport {
  BaselineFit linear;
  DeadReckoningResult linear_trajectory;
  LandmarkDecision linear_decision;
  JointResult joint;
  DeadReckoningResult joint_trajectory;
  LandmarkDecision joint_decision;
};

std::string JointTable(const JointReport& report, bool full_solver_report);
nlohmann::json JointJson(const JointReport& report);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_JOINT_REPORT_H_
