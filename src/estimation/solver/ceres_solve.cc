#include "estimation/solver/ceres_solve.h"

#include <memory>

namespace accelcal {

namespace {

Status Solve(const QuietSolveOptions& options, const std::vector<double*>& eliminated,
             ceres::Problem* problem, SolverReport* report, bool sparse = false) {
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = sparse ? ceres::SPARSE_NORMAL_CHOLESKY : ceres::DENSE_QR;
  if (!eliminated.empty()) {
    solver_options.linear_solver_type = ceres::DENSE_SCHUR;
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    std::vector<double*> blocks;
    problem->GetParameterBlocks(&blocks);
    for (double* block : blocks) ordering->AddElementToGroup(block, 1);
    for (double* block : eliminated) ordering->AddElementToGroup(block, 0);
    solver_options.linear_solver_ordering = ordering;
  }
  solver_options.initial_trust_region_radius = options.initial_trust_region_radius;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = options.tolerance;
  solver_options.gradient_tolerance = options.tolerance;
  solver_options.parameter_tolerance = options.tolerance;
  solver_options.num_threads = options.num_threads;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, problem, &summary);
  report->brief_report = summary.BriefReport();
  report->full_report = summary.FullReport();
  report->iterations = static_cast<int>(summary.iterations.size());
  report->residual_blocks = summary.num_residual_blocks;
  report->residuals = summary.num_residuals;
  report->converged = summary.termination_type == ceres::CONVERGENCE;
  if (report->converged) return Status::Ok();
  if (summary.termination_type == ceres::NO_CONVERGENCE) {
    // The advice is the caller's: only some binaries have a flag for the iterations (joint's
    // --max_iterations), and a suggestion must be one that works (issue 45).
    return Status::Error("Ceres did not converge in " + std::to_string(report->iterations) +
                         " iterations: " + summary.message);
  }
  if (summary.message.find("evaluation failed") != std::string::npos) {
    // The model has no value where the solver went (e.g. 1 + scale <= 0, or a quadratic
    // sensor without a real inverse): the data determine the parameters too weakly.
    return Status::Error(
        "Ceres did not converge: the model could not be evaluated at the "
        "parameters it reached (a non-finite residual or Jacobian), so these "
        "data determine the chosen effects too weakly; estimate fewer effects or "
        "use a test with more angles");
  }
  return Status::Error("Ceres did not converge: " + summary.message);
}

}  // namespace

Status SolveQuietly(const QuietSolveOptions& options, ceres::Problem* problem,
                    SolverReport* report) {
  return Solve(options, {}, problem, report);
}

Status SolveQuietlySparse(const QuietSolveOptions& options, ceres::Problem* problem,
                          SolverReport* report) {
  return Solve(options, {}, problem, report, true);
}

Status SolveQuietlyEliminating(const QuietSolveOptions& options,
                               const std::vector<double*>& eliminated, ceres::Problem* problem,
                               SolverReport* report) {
  return Solve(options, eliminated, problem, report);
}

}  // namespace accelcal
