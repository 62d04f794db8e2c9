#include "reporting/trajectory_report.h"

#include <cmath>

#include "common/format.h"
#include "reporting/estimate_json.h"

namespace accelcal {
namespace {

nlohmann::json Matrix2(const Eigen::Matrix2d& m) {
  return {{m(0, 0), m(0, 1)}, {m(1, 0), m(1, 1)}};
}

nlohmann::json Point(const Eigen::Vector2d& p) { return {{"x", p.x()}, {"y", p.y()}}; }

std::string DecisionLine(const LandmarkDecision& decision) {
  if (decision.best < 0) return "no landmarks to decide among";
  const LandmarkScore& best = decision.scores[decision.best];
  if (decision.consistent) {
    // clang-format off
    return StringPrintf(
        "the vehicle reached %s (posterior %.4f under equal priors; its Mahalanobis distance %.2f has p-value %.3g)",
        best.landmark.name.c_str(), best.posterior, std::sqrt(best.mahalanobis2), best.p_value);
  }
  return StringPrintf(
      "no landmark is consistent with the endpoint: the closest, %s, is at Mahalanobis distance %.2f (p-value %.3g < alpha %.3g)",
      // clang-format on
      best.landmark.name.c_str(), std::sqrt(best.mahalanobis2), best.p_value, decision.alpha);
}

}  // namespace

std::string TrajectoryTable(const TrajectoryReport& report) {
  const DeadReckoningResult& t = report.trajectory;
  std::string text =
      "accelcal trajectory: dead reckoning of the vehicle run, corrected by the baseline fit\n";
  auto file = [&](const char* role) {
    const auto found = report.input_files.find(role);
    return found == report.input_files.end() ? std::string("-") : found->second;
  };
  text += StringPrintf("  run          %s (%d samples, dt %.4g s, %.2f s)\n", file("run").c_str(),
                       t.sample_count, t.dt_s, t.duration_s);
  text +=
      StringPrintf("  start        p0 = (%g, %g) m, v0 = (%g, %g) m/s  [%s]\n",
                   report.conditions.initial_position_x_m, report.conditions.initial_position_y_m,
                   report.conditions.initial_velocity_x_mps,
                   report.conditions.initial_velocity_y_mps, file("conditions").c_str());
  text +=
      StringPrintf("  calibration  %s: bias_x %+.4e, scale_x %+.4e, bias_y %+.4e, scale_y %+.4e\n",
                   file("calibration").c_str(), report.fit.Value(Parameter::kBiasX),
                   report.fit.Value(Parameter::kScaleX), report.fit.Value(Parameter::kBiasY),
                   report.fit.Value(Parameter::kScaleY));
  text += "\n  verdict: " + DecisionLine(report.decision) + "\n\n";

  text += "  endpoint            x (m)      y (m)   1 sigma x, y (m)\n";
  text +=
      StringPrintf("  corrected      %10.3f %10.3f   %.2f, %.2f\n", t.endpoint.x(), t.endpoint.y(),
                   std::sqrt(t.covariance(0, 0)), std::sqrt(t.covariance(1, 1)));
  text +=
      StringPrintf("  raw            %10.3f %10.3f\n\n", t.raw_endpoint.x(), t.raw_endpoint.y());

  text += "  endpoint covariance (m^2)        xx         xy         yy\n";
  for (const auto& [name, m] :
       {std::make_pair("parameters J S J^T", t.parameter_part),
        std::make_pair("run's own noise", t.noise_part), std::make_pair("total", t.covariance)}) {
    text += StringPrintf("  %-26s %10.3f %10.3f %10.3f\n", name, m(0, 0), m(0, 1), m(1, 1));
  }

  text +=
      "\n  landmark        x (m)      y (m)  distance (m)  Mahalanobis^2   posterior    p-value\n";
  for (const LandmarkScore& score : report.decision.scores) {
    text += StringPrintf("  %-8s %10.3f %10.3f  %12.2f  %13.3f  %10.3g  %9.3g\n",
                         score.landmark.name.c_str(), score.landmark.x_m, score.landmark.y_m,
                         score.distance_m, score.mahalanobis2, score.posterior, score.p_value);
  }

  text += "\n  the report's bound (section 4) against the correct 3-sigma of each term (m)\n";
  text += "  axis  term     report's bound   correct 3 sigma   share of variance\n";
  for (const AxisErrorBudget& b : report.budget) {
    for (const auto& [name, term] :
         {std::make_pair("bias", b.bias), std::make_pair("scale", b.scale),
          std::make_pair("noise", b.noise)}) {
      text += StringPrintf("  %-4s  %-6s %14.2f %17.2f %18.1f%%\n", b.axis, name, term.report_m,
                           term.three_sigma_m, 100.0 * term.variance_share);
    }
    text += StringPrintf("  %-4s  %-6s %14.2f %17.2f\n", b.axis, "total", b.report_bound_m,
                         b.three_sigma_m);
  }
  for (const AxisErrorBudget& b : report.budget) {
    const BudgetTerm& dominant = std::string(b.dominant) == "bias"    ? b.bias
                                 : std::string(b.dominant) == "scale" ? b.scale
                                                                      : b.noise;
    // clang-format off
    text += StringPrintf(
        "  %s: the %s term dominates (%.0f%% of the endpoint variance). The report's noise term, 3 sigma_eta = %.2f m, is %.1f times too %s: the correct one is %.2f m, because the run's noise is integrated twice over %.0f s and grows as sigma sqrt(dt T^3/3).\n",
        // clang-format on
        b.axis, b.dominant, 100.0 * dominant.variance_share, b.noise.report_m,
        b.noise.three_sigma_m >= b.noise.report_m ? b.noise.three_sigma_m / b.noise.report_m
                                                  : b.noise.report_m / b.noise.three_sigma_m,
        b.noise.three_sigma_m >= b.noise.report_m ? "small" : "large", b.noise.three_sigma_m,
        t.duration_s);
  }
  return text;
}

nlohmann::json TrajectoryJson(const TrajectoryReport& report) {
  const DeadReckoningResult& t = report.trajectory;
  nlohmann::json budget = nlohmann::json::array();
  for (const AxisErrorBudget& b : report.budget) {
    auto term = [](const BudgetTerm& term) {
      return nlohmann::json{{"report_m", term.report_m},
                            {"three_sigma_m", term.three_sigma_m},
                            {"variance_share", term.variance_share}};
    };
    budget.push_back({{"axis", b.axis},
                      {"bias", term(b.bias)},
                      {"scale", term(b.scale)},
                      {"noise", term(b.noise)},
                      {"report_bound_m", b.report_bound_m},
                      {"three_sigma_m", b.three_sigma_m},
                      {"dominant", b.dominant},
                      {"report_noise_term_factor", b.noise.three_sigma_m / b.noise.report_m}});
  }
  nlohmann::json jacobian = nlohmann::json::array();
  nlohmann::json columns = nlohmann::json::array();
  for (const Parameter parameter : t.jacobian_columns) columns.push_back(Info(parameter).name);
  for (int r = 0; r < 2; ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int c = 0; c < t.jacobian.cols(); ++c) row.push_back(t.jacobian(r, c));
    jacobian.push_back(row);
  }
  const LandmarkDecision& decision = report.decision;
  nlohmann::json json = {
      {"problem", "trajectory"},
      {"endpoint", Point(t.endpoint)},
      {"raw_endpoint", Point(t.raw_endpoint)},
      {"end_velocity", Point(t.end_velocity)},
      {"endpoint_covariance", Matrix2(t.covariance)},
      {"parameter_part", Matrix2(t.parameter_part)},
      {"noise_part", Matrix2(t.noise_part)},
      {"jacobian", {{"rows", {"x", "y"}}, {"columns", columns}, {"matrix", jacobian}}},
      {"landmarks", LandmarkScoresJson(decision)},
      {"reached", ReachedJson(decision)},
      {"best", decision.best >= 0 ? nlohmann::json(decision.scores[decision.best].landmark.name)
                                  : nlohmann::json(nullptr)},
      {"p_value", decision.best >= 0 ? nlohmann::json(decision.scores[decision.best].p_value)
                                     : nlohmann::json(nullptr)},
      {"landmark_alpha", decision.alpha},
      {"error_budget", budget},
      {"baseline", ParameterEstimateJson(FromBaselineFit(report.fit))},
      {"run", {{"samples", t.sample_count}, {"dt_s", t.dt_s}, {"duration_s", t.duration_s}}}};
  return json;
}

std::string TrajectoryPathCsv(const DeadReckoningResult& trajectory) {
  // clang-format off
  std::string text =
      "t_s,x_m,y_m,raw_x_m,raw_y_m,cov_xx,cov_xy,cov_yy,parameter_cov_xx,parameter_cov_xy,parameter_cov_yy,noise_cov_xx,noise_cov_yy\n";
  // clang-format on
  for (const PathPoint& p : trajectory.path) {
    const Eigen::Matrix2d total = p.parameter_covariance + p.noise_covariance;
    text += StringPrintf(
        "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", p.timestamp_s,
        p.position.x(), p.position.y(), p.raw_position.x(), p.raw_position.y(), total(0, 0),
        total(0, 1), total(1, 1), p.parameter_covariance(0, 0), p.parameter_covariance(0, 1),
        p.parameter_covariance(1, 1), p.noise_covariance(0, 0), p.noise_covariance(1, 1));
  }
  return text;
}

}  // namespace accelcal
