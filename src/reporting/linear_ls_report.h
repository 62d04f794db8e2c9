#ifndef ACCELCAL_REPORTING_LINEAR_LS_REPORT_H_
#define ACCELCAL_REPORTING_LINEAR_LS_REPORT_H_

// What linear_ls prints and writes: a table a person reads (estimates +- 1 sigma,
// correlation, chi-square against the stated noise, agreement of the two solvers) and
// the JSON a program reads. Formatting only: nothing here estimates anything.

#include <Eigen/Core>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "estimation/tilt_table/baseline_parameters.h"
#include "estimation/tilt_table/ceres_linear_ls.h"
#include "models/effects.h"

namespace accelcal {

struct LinearLsReport {
  BaselineFit closed_form;
  CeresLinearLsResult ceres;
  // Why the Ceres cross-check did not run (a test too large to hold), or "" when it did;
  // the table and the JSON then give this reason in its place.
  std::string ceres_skipped;
  double gravity_mps2 = 9.8;
  double noise_variance_x = 0.0;
  double noise_variance_y = 0.0;
  double theta_min_rad = 0.0;
  double theta_max_rad = 0.0;
  std::map<std::string, std::string> input_files;  // role ("calibration", ...) -> path
  // Set when the data were simulated: the seed and the true parameters.
  std::optional<uint64_t> simulation_seed;
  std::string scenario_name;
  std::optional<Eigen::Vector4d> truth;
};

std::string LinearLsTable(const LinearLsReport& report, bool full_solver_report);
nlohmann::json LinearLsJson(const LinearLsReport& report);

// The baseline's four parameters out of a full set (a simulation's truth), in BaselineIndex
// order, to stand beside the estimates.
Eigen::Vector4d BaselineTruth(const ModelParameters<double>& parameters);

// Why the Ceres cross-check does not run on a test of `samples` samples when it runs on at
// most `max_samples` (linear_ls' --ceres_max_samples), or "" when it does run.
std::string CeresSkippedReason(long long samples, long long max_samples);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_LINEAR_LS_REPORT_H_
