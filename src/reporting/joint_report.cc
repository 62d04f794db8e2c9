#include "reporting/joint_report.h"

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "common/format.h"
#include "estimation/tilt_table/parameter_estimate.h"
#include "reporting/estimate_json.h"

namespace accelcal {
namespace {

std::string Cell(double value, double sigma) { return StringPrintf("%+.4e +- %.2e", value, sigma); }

// The parameters fitted beyond bias and scale, for the text and the JSON alike.
std::vector<std::string> EffectNames(const JointReport& report) {
  std::vector<std::string> names;
  for (const Parameter parameter : report.joint.estimate.free) {
    if (!Info(parameter).baseline) names.push_back(Info(parameter).name);
  }
  return names;
}

// "angle_offset,nonorthogonality", or "none".
std::string EffectsText(const JointReport& report) {
  std::string text;
  for (const std::string& name : EffectNames(report)) text += (text.empty() ? "" : ",") + name;
  return text.empty() ? "none" : text;
}

// The joint fit's degrees of freedom: both axes' samples and the endpoint's two residuals
// when tied, less the free parameters.
int JointDof(const JointReport& report) {
  return 2 * report.joint.samples + (report.joint.landmark.empty() ? 0 : 2) -
         static_cast<int>(report.joint.estimate.free.size());
}

}  // namespace

std::string JointTable(const JointReport& report, bool full_solver_report) {
  const ParameterEstimate linear = FromBaselineFit(report.linear);
  const ParameterEstimate& joint = report.joint.estimate;
  std::string text = StringPrintf(
      "accelcal joint: the linear baseline and the joint nonlinear model (effects: %s; run %s)\n\n",
      EffectsText(report).c_str(),
      report.joint.landmark.empty() ? "not tied to a landmark"
                                    : ("tied to " + report.joint.landmark).c_str());
  // clang-format off
  text +=
      "  parameter              unit        linear (bias, scale only)       joint                     shift\n";
  // clang-format on
  for (const Parameter parameter : joint.free) {
    const ParameterInfo& info = Info(parameter);
    const int linear_index = linear.IndexOf(parameter);
    const std::string linear_cell =
        linear_index >= 0 ? Cell(linear.Value(parameter), linear.StandardDeviation(parameter))
                          : StringPrintf("%-26s", "(not in the model)");
    const std::string shift =
        linear_index >= 0
            ? StringPrintf("%+7.2f sigma", (joint.Value(parameter) - linear.Value(parameter)) /
                                               linear.StandardDeviation(parameter))
            : "";
    text += StringPrintf("  %-22s %-10s  %s   %s  %s\n", info.name, info.unit, linear_cell.c_str(),
                         Cell(joint.Value(parameter), joint.StandardDeviation(parameter)).c_str(),
                         shift.c_str());
  }
  text += StringPrintf("\n  chi-square           linear          joint\n");
  text += StringPrintf("  tilt test x    %12.1f   %12.1f\n", report.linear.chi2_x.chi2,
                       report.joint.chi2_x);
  text += StringPrintf("  tilt test y    %12.1f   %12.1f\n", report.linear.chi2_y.chi2,
                       report.joint.chi2_y);
  if (!report.joint.landmark.empty()) {
    text += StringPrintf("  endpoint       %12s   %12.2f   (2 residuals, tied to %s)\n", "-",
                         report.joint.chi2_endpoint, report.joint.landmark.c_str());
  }
  text += StringPrintf("  (degrees of freedom: linear %d per axis; joint %d over both axes%s)\n",
                       report.linear.chi2_x.dof, JointDof(report),
                       report.joint.landmark.empty() ? "" : " and the endpoint");

  text += "\n  endpoint (m)            x          y     1 sigma x, y    reached\n";
  for (const auto& [name, trajectory, decision] :
       {std::make_tuple("linear", &report.linear_trajectory, &report.linear_decision),
        std::make_tuple("joint", &report.joint_trajectory, &report.joint_decision)}) {
    text += StringPrintf("  %-10s     %10.3f %10.3f   %6.2f, %6.2f   %s\n", name,
                         trajectory->endpoint.x(), trajectory->endpoint.y(),
                         std::sqrt(trajectory->covariance(0, 0)),
                         std::sqrt(trajectory->covariance(1, 1)),
                         decision->reached.empty() ? "none consistent" : decision->reached.c_str());
  }
  if (!report.joint.hypotheses.empty()) {
    text += "\n  landmark hypotheses (one joint solve each)   cost   endpoint chi2   posterior\n";
    for (const LandmarkHypothesis& hypothesis : report.joint.hypotheses) {
      if (!hypothesis.solved) {
        text += StringPrintf("  %-40s not solved: %.3g sigma from the baseline endpoint\n",
                             hypothesis.name.c_str(), hypothesis.baseline_sigma);
        continue;
      }
      text += StringPrintf("  %-40s %10.2f %15.2f %11.3g\n", hypothesis.name.c_str(),
                           hypothesis.cost, hypothesis.chi2_endpoint, hypothesis.posterior);
    }
    // clang-format off
    text +=
        "  (when the run is tied to a landmark, the joint endpoint is pulled toward it: choose the\n"
        // clang-format on
        "   landmark by the hypotheses' posteriors, not by the joint endpoint's table)\n";
  }
  text += "\n  " + report.joint.solver.brief_report + "\n";
  if (full_solver_report) text += report.joint.solver.full_report + "\n";
  return text;
}

nlohmann::json JointJson(const JointReport& report) {
  nlohmann::json hypotheses = nlohmann::json::array();
  for (const LandmarkHypothesis& hypothesis : report.joint.hypotheses) {
    const auto if_solved = [&](double value) {
      return hypothesis.solved ? nlohmann::json(value) : nlohmann::json(nullptr);
    };
    hypotheses.push_back({{"name", hypothesis.name},
                          {"solved", hypothesis.solved},
                          {"baseline_sigma", hypothesis.baseline_sigma},
                          {"cost", if_solved(hypothesis.cost)},
                          {"chi2_endpoint", if_solved(hypothesis.chi2_endpoint)},
                          {"posterior", hypothesis.posterior}});
  }
  const auto tied = [&](double chi2) {
    return report.joint.landmark.empty() ? std::optional<double>() : std::optional<double>(chi2);
  };
  return {{"problem", "joint"},
          {"effects", EffectNames(report)},
          {"dof", {{"linear_per_axis", report.linear.chi2_x.dof}, {"joint", JointDof(report)}}},
          {"tied_landmark", report.joint.landmark.empty() ? nlohmann::json(nullptr)
                                                          : nlohmann::json(report.joint.landmark)},
          {"linear", SolutionJson(FromBaselineFit(report.linear), report.linear.chi2_x.chi2,
                                  report.linear.chi2_y.chi2, std::nullopt, report.linear_trajectory,
                                  report.linear_decision)},
          {"joint", SolutionJson(report.joint.estimate, report.joint.chi2_x, report.joint.chi2_y,
                                 tied(report.joint.chi2_endpoint), report.joint_trajectory,
                                 report.joint_decision)},
          {"hypotheses", hypotheses},
          {"solver",
           {{"converged", report.joint.solver.converged},
            {"iterations", report.joint.solver.iterations},
            {"brief_report", report.joint.solver.brief_report}}}};
}

}  // namespace accelcal
