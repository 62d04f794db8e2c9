#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_ERROR_BUDGET_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_ERROR_BUDGET_H_

// The endpoint error budget per axis, term by term, beside the reference report's bound
// (seed-report.md, section 4):
//
//   report:   delta_p < t_f^2/2 (3 sigma_b + 3 |a_max| sigma_s) + 3 sigma_eta
//   correct:  bias   3 |d p/d b| sigma_b
//             scale  3 |d p/d s| sigma_s            (d p/d s = -sum_j w_j a_j / (1 + s))
//             noise  3 sqrt(sum_j w_j^2) sigma / (1 + s)  ~ 3 sigma sqrt(dt T^3 / 3)
//
// t_f is the run's duration, a_max the largest |measured acceleration| of the axis and
// sigma_eta the stated noise standard deviation of one sample.

#include <array>
#include <string>

#include "common/measurements.h"
#include "estimation/tilt_table/baseline_parameters.h"
#include "estimation/tilt_table/trajectory.h"

namespace accelcal {

struct BudgetTerm {
  double report_m = 0.0;        // the report's term
  double three_sigma_m = 0.0;   // the correct 3-sigma of the same term
  double variance_share = 0.0;  // its share of the endpoint variance of the axis
};

struct AxisErrorBudget {
  const char* axis = "x";
  BudgetTerm bias;
  BudgetTerm scale;
  BudgetTerm noise;
  double report_bound_m = 0.0;     // the report's total
  double three_sigma_m = 0.0;      // 3 sqrt(endpoint variance of the axis), all terms
  const char* dominant = "noise";  // "bias", "scale" or "noise"
};

std::array<AxisErrorBudget, 2> ComputeErrorBudget(const DeadReckoningResult& trajectory,
                                                  const BaselineFit& fit, const VehicleRun& run,
                                                  const RunConditions& conditions);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_ERROR_BUDGET_H_
