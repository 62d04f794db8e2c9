#ifndef ACCELCAL_ESTIMATION_SOLVER_SOLVER_REPORT_H_
#define ACCELCAL_ESTIMATION_SOLVER_SOLVER_REPORT_H_

// What a Ceres solve reports back, kept free of Ceres types so reporting/ can read it.

#include <string>

namespace accelcal {

struct SolverReport {
  bool converged = false;
  int iterations = 0;
  // The size of the problem as it was handed to Ceres (before any preprocessing).
  int residual_blocks = 0;
  int residuals = 0;
  std::string brief_report;  // ceres::Solver::Summary::BriefReport()
  std::string full_report;   // ceres::Solver::Summary::FullReport()
};

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_SOLVER_SOLVER_REPORT_H_
