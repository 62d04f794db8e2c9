#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_SCORE_TEST_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_SCORE_TEST_H_

// Discovery's score test: how much chi-square each candidate effect would remove if it were
// added to a solved model, without solving the extended model. With r the whitened
// residuals at the solution, J_A the Jacobian of its free parameters and j_c a candidate's
// column,
//
//   delta chi2_c = (e^T r)^2 / (e^T e),   e = j_c projected off the span of J_A
//
// (at an optimum J_A^T r = 0, so only the part of j_c the model cannot already produce can
// reduce chi-square). Exact for an effect linear in its parameter, first order otherwise.
// One Jacobian evaluation serves every candidate, which is what makes discovery fast.

#include <vector>

#include "common/status.h"
#include "estimation/tilt_table/joint_estimator.h"

namespace accelcal {

class JointData;

// `current` is a SolveJoint result for `data` and `options`. A candidate whose column the
// model already spans scores 0.
Status ScoreCandidates(const JointData& data, const JointOptions& options,
                       const JointResult& current, const std::vector<Parameter>& candidates,
                       std::vector<double>* delta_chi2);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_SCORE_TEST_H_
