#ifndef ACCELCAL_ESTIMATION_SOLVER_IDENTIFIABILITY_H_
#define ACCELCAL_ESTIMATION_SOLVER_IDENTIFIABILITY_H_

// Whether the data determine a set of parameters: the information matrix J^T J of the
// whitened residuals, its columns scaled to unit norm, is checked for
//
//   - a zero diagonal entry: no residual depends on that parameter; and
//   - a near-null direction: an eigenvalue below `threshold` times the largest, whose
//     eigenvector names the parameters that move together along it (|component| > 0.1).
//
// Either way the parameters are named, so a user learns what to fix or which test design to
// change, and no covariance is claimed for them. Geometry-free: any sensor's problem that
// can form J^T J asks the same question.

#include <Eigen/Core>
#include <vector>

#include "common/status.h"
#include "models/effects.h"

namespace accelcal {

// `information` is p x p, in the order of `parameters`.
Status CheckIdentifiable(const Eigen::MatrixXd& information,
                         const std::vector<Parameter>& parameters, double threshold);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_SOLVER_IDENTIFIABILITY_H_
