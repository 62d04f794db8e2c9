#include "reporting/linear_ls_report.h"

#include "common/format.h"
#include "reporting/estimate_json.h"

namespace accelcal {
namespace {

nlohmann::json Named(const Eigen::Vector4d& values) {
  nlohmann::json object = nlohmann::json::object();
  for (const Parameter parameter : kBaselineParameters) {
    object[Info(parameter).name] = values[BaselineIndex(parameter)];
  }
  return object;
}

nlohmann::json Matrix(const Eigen::Matrix4d& matrix) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 4; ++i) {
    rows.push_back({matrix(i, 0), matrix(i, 1), matrix(i, 2), matrix(i, 3)});
  }
  return rows;
}

nlohmann::json FitJson(const BaselineFit& fit) {
  nlohmann::json json = ParameterEstimateJson(FromBaselineFit(fit));
  json["chi2"] = {{"x", fit.chi2_x.chi2}, {"y", fit.chi2_y.chi2}};
  return json;
}

}  // namespace

std::string LinearLsTable(const LinearLsReport& report, bool full_solver_report) {
  const BaselineFit& fit = report.closed_form;
  const Eigen::Vector4d sigma = fit.StandardDeviations();
  std::string text =
      "accelcal linear_ls: bias and scale factor from the tilt-table test (linear least squares)\n";
  if (report.simulation_seed) {
    // clang-format off
    text += StringPrintf(
        "  data         simulated in-process: scenario %s, seed %llu, %d samples, theta %.3f to %.3f rad\n",
        // clang-format on
        report.scenario_name.c_str(), static_cast<unsigned long long>(*report.simulation_seed),
        fit.sample_count, report.theta_min_rad, report.theta_max_rad);
    text += "               (no --data_dir given; try --data_dir=../shared/data/tp2-2018)\n";
  } else {
    auto file = [&](const char* role) {
      const auto found = report.input_files.find(role);
      return found == report.input_files.end() ? std::string("-") : found->second;
    };
    text += StringPrintf("  calibration  %s (%d samples, theta %.3f to %.3f rad)\n",
                         file("calibration").c_str(), fit.sample_count, report.theta_min_rad,
                         report.theta_max_rad);
    text += StringPrintf("  conditions   %s\n", file("conditions").c_str());
  }
  text += StringPrintf("  stated noise variance x %g, y %g (m/s^2)^2; g = %g m/s^2\n\n",
                       report.noise_variance_x, report.noise_variance_y, report.gravity_mps2);

  text += report.truth
              ? "  parameter      estimate     1 sigma  unit        truth  (est-truth)/sigma\n"
              : "  parameter      estimate     1 sigma  unit\n";
  for (const Parameter parameter : kBaselineParameters) {
    const int i = BaselineIndex(parameter);
    const ParameterInfo& info = Info(parameter);
    text += StringPrintf("  %-9s  %+.4e  %.4e  ", info.name, fit.parameters[i], sigma[i]);
    text += report.truth ? StringPrintf("%-5s", info.unit) : info.unit;
    if (report.truth) {
      text += StringPrintf("  %+.4e  %+6.2f", (*report.truth)[i],
                           (fit.parameters[i] - (*report.truth)[i]) / sigma[i]);
    }
    text += "\n";
  }

  const Eigen::Matrix4d correlation = fit.Correlation();
  text += "\n  correlation ";
  for (const Parameter parameter : kBaselineParameters) {
    text += StringPrintf(" %7s", Info(parameter).name);
  }
  text += "\n";
  for (const Parameter parameter : kBaselineParameters) {
    const int i = BaselineIndex(parameter);
    text += StringPrintf("  %-11s ", Info(parameter).name);
    for (int j = 0; j < kBaselineParameterCount; ++j)
      text += StringPrintf(" %+7.4f", correlation(i, j));
    text += "\n";
  }

  text += "\n  fit vs stated noise        chi2    dof  chi2/dof  p (two-sided)\n";
  for (const auto& [name, chi2] :
       {std::make_pair("x", fit.chi2_x), std::make_pair("y", fit.chi2_y)}) {
    text += StringPrintf("  axis %s             %12.1f  %5d  %8.4f  %.3g\n", name, chi2.chi2,
                         chi2.dof, chi2.chi2 / chi2.dof, chi2.p_value);
  }

  if (!report.ceres_skipped.empty()) {
    return text + "\n  closed form only; " + report.ceres_skipped + "\n";
  }
  const FitDifference difference = CompareFits(fit, report.ceres.fit);
  // clang-format off
  text += StringPrintf(
      "\n  closed form vs Ceres: parameters agree to %.1e (relative), covariance to %.1e (relative to sqrt(C_ii C_jj))\n",
      // clang-format on
      difference.parameters, difference.covariance);
  text += "  " + report.ceres.solver.brief_report + "\n";
  if (full_solver_report) text += report.ceres.solver.full_report + "\n";
  return text;
}

nlohmann::json LinearLsJson(const LinearLsReport& report) {
  const BaselineFit& fit = report.closed_form;
  nlohmann::json json = FitJson(fit);
  json["problem"] = "linear_ls";
  json["correlation"] = Matrix(fit.Correlation());
  json["dof"] = {{"x", fit.chi2_x.dof}, {"y", fit.chi2_y.dof}};
  json["chi2_p_value"] = {{"x", fit.chi2_x.p_value}, {"y", fit.chi2_y.p_value}};
  json["n_samples"] = fit.sample_count;
  json["gravity_mps2"] = report.gravity_mps2;
  json["noise_variance"] = {{"x", report.noise_variance_x}, {"y", report.noise_variance_y}};
  json["theta_range_rad"] = {report.theta_min_rad, report.theta_max_rad};
  json["simulation"] = nullptr;
  if (report.simulation_seed) {
    json["simulation"] = {{"scenario", report.scenario_name},
                          {"seed", *report.simulation_seed},
                          {"truth", Named(*report.truth)}};
  }
  if (!report.ceres_skipped.empty()) {
    json["solvers"] = {{"closed_form", FitJson(fit)},
                       {"ceres", nullptr},
                       {"max_relative_difference", nullptr},
                       {"ceres_skipped", report.ceres_skipped}};
    return json;
  }
  const FitDifference difference = CompareFits(fit, report.ceres.fit);
  nlohmann::json ceres = FitJson(report.ceres.fit);
  ceres["converged"] = report.ceres.solver.converged;
  ceres["iterations"] = report.ceres.solver.iterations;
  ceres["brief_report"] = report.ceres.solver.brief_report;
  json["solvers"] = {
      {"closed_form", FitJson(fit)},
      {"ceres", ceres},
      {"max_relative_difference",
       {{"parameters", difference.parameters}, {"covariance", difference.covariance}}},
      {"ceres_skipped", nullptr}};
  return json;
}

Eigen::Vector4d BaselineTruth(const ModelParameters<double>& parameters) {
  Eigen::Vector4d truth;
  for (const Parameter parameter : kBaselineParameters) {
    truth[BaselineIndex(parameter)] = parameters[parameter];
  }
  return truth;
}

std::string CeresSkippedReason(long long samples, long long max_samples) {
  if (samples <= max_samples) return "";
  return "Ceres skipped: " + std::to_string(samples) +
         " samples, more than --ceres_max_samples=" + std::to_string(max_samples) +
         " (it would hold them all with their residuals in memory)";
}

}  // namespace accelcal
