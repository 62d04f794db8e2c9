#ifndef ACCELCAL_ESTIMATION_SOLVER_CERES_SOLVE_H_
#define ACCELCAL_ESTIMATION_SOLVER_CERES_SOLVE_H_

// The one way the estimators run Ceres: Levenberg-Marquardt with dense QR, tight
// tolerances (these problems are small and well scaled, and the comparisons with closed
// forms are limited by rounding, not by stopping early), and no logging.

#include <ceres/ceres.h>

#include <vector>

#include "common/status.h"
#include "estimation/solver/solver_report.h"

namespace accelcal {

struct QuietSolveOptions {
  int max_iterations = 100;
  int num_threads = 1;
  double tolerance = 1e-14;                  // function, gradient and parameter tolerance
  double initial_trust_region_radius = 1e4;  // Ceres' default
};

// Fills `report` whatever happens; fails with Ceres' message when it did not converge.
Status SolveQuietly(const QuietSolveOptions& options, ceres::Problem* problem,
                    SolverReport* report);

// The same with Ceres' DENSE_SCHUR linear solver, `eliminated` (blocks no residual shares with
// another of them, e.g. one nuisance block per measurement group) eliminated first: each LM step
// costs a pass over the residuals plus a dense solve in the other blocks alone, instead of a dense
// QR in all of them. The same steps up to rounding.
Status SolveQuietlyEliminating(const QuietSolveOptions& options,
                               const std::vector<double*>& eliminated, ceres::Problem* problem,
                               SolverReport* report);

// The same with Ceres' SPARSE_NORMAL_CHOLESKY (SuiteSparse in Debian's Ceres): for a problem whose
// nuisance blocks are linked in a chain (the gyroscope's turns join consecutive poses' directions,
// so no independent set eliminates them), each step costs what its sparse normal equations do,
// linear in the chain's length.
Status SolveQuietlySparse(const QuietSolveOptions& options, ceres::Problem* problem,
                          SolverReport* report);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_SOLVER_CERES_SOLVE_H_
