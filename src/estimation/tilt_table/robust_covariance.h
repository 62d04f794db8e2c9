#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_ROBUST_COVARIANCE_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_ROBUST_COVARIANCE_H_

// The covariance of an M-estimate. ceres::Covariance inverts the loss-corrected information
// matrix, which is right only when the residuals follow the distribution the loss assumes.
// Under heavy tails (docs/noise-models.md) the Huber fit's covariance is the sandwich
//
//   A^-1 B A^-1,   A = sum psi'(r_i) J_i J_i^T,   B = sum psi(r_i)^2 J_i J_i^T
//
// over the tilt-test rows (psi the Huber influence at the loss's scale), plus J^T J for the
// endpoint's rows, which carry no loss. It holds for independent noise of any distribution
// with finite variance.

#include "common/status.h"
#include "estimation/tilt_table/joint_estimator.h"

namespace accelcal {

class JointData;

// Replaces the covariance of `result` (a SolveJoint solution for `data` with
// options.loss = RobustLoss::kHuber) by the sandwich.
Status HuberSandwichCovariance(const JointData& data, const JointOptions& options,
                               JointResult* result);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_ROBUST_COVARIANCE_H_
