#ifndef ACCELCAL_ESTIMATION_SOLVER_REPORT_H_
#define ACCELCAL_ESTIMATION_SOLVER_REPORT_H_

// What a Ceres solve reports back, kept free of Ceres types so reporting/ can read it.

#include <string>

namespace accelcal {

struct SolverReport {
  bool converged = false;
  int iterations = 0;
  std::string brief_report;  // ceres::Solver::Summary::BriefReport()
  std::string full_report;   // ceres::Solver::Summary::FullReport()
};

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_SOLVER_REPORT_H_
