#include "reporting/min_samples_report.h"

#include <Eigen/Dense>
#include <array>
#include <cmath>

#include "common/format.h"

namespace accelcal {
namespace {

const char* CheckKindName(MonteCarloCheck::Kind kind) {
  switch (kind) {
    case MonteCarloCheck::Kind::kFullSimulation:
      return "full_simulation";
    case MonteCarloCheck::Kind::kRealTestSubsets:
      return "real_test_subsets";
    case MonteCarloCheck::Kind::kRealTestEvenSubsets:
      return "real_test_even_subsets";
  }
  return "";
}

std::string CheckLine(const MonteCarloCheck& check) {
  if (check.kind == MonteCarloCheck::Kind::kFullSimulation) {
    return StringPrintf(
        "  full simulation, N = %5d: P(wrong) analytic %.4f, Monte Carlo %.4f +- %.4f (%d runs)\n",
        check.samples, check.analytic, check.monte_carlo, check.monte_carlo_sd, check.repetitions);
  }
  const bool evenly = check.kind == MonteCarloCheck::Kind::kRealTestEvenSubsets;
  return StringPrintf(
      "  %s of the real test, N = %5d: P(wrong) analytic %.4f, Monte Carlo %.4f +- %.4f%s\n",
      evenly ? "evenly spaced subsets" : "random subsets", check.samples, check.analytic,
      check.monte_carlo, check.monte_carlo_sd,
      evenly ? StringPrintf(" (%d disjoint subsets)", check.independent).c_str() : "");
}

// Why the report's per-axis N is so large, from this data's numbers.
std::string Explanation(const MinSamplesReport& report) {
  const EndpointModel& model = report.study.model;
  const std::vector<Landmark>& landmarks = report.landmarks;
  const int truth = report.study.truth;
  const Landmark& t = landmarks[truth];
  std::array<double, 2> d_min = {HUGE_VAL, HUGE_VAL};
  std::array<std::string, 2> against;
  double nearest_2d = HUGE_VAL;
  std::string nearest_name;
  const Eigen::Matrix2d inverse_noise = model.noise_part.inverse();
  for (size_t k = 0; k < landmarks.size(); ++k) {
    if (static_cast<int>(k) == truth) continue;
    const Eigen::Vector2d d(landmarks[k].x_m - t.x_m, landmarks[k].y_m - t.y_m);
    for (int axis = 0; axis < 2; ++axis) {
      if (std::abs(d[axis]) < d_min[axis]) {
        d_min[axis] = std::abs(d[axis]);
        against[axis] = landmarks[k].name;
      }
    }
    const double separation = std::sqrt(d.dot(inverse_noise * d));
    if (separation < nearest_2d) {
      nearest_2d = separation;
      nearest_name = landmarks[k].name;
    }
  }
  // The N quoted is the uniform design's when it ran, else the first design's that meets the
  // criterion (uniform_n_min is only a search default when the uniform design did not run).
  std::string n_min_text =
      "no design run here reaches P(wrong) <= " + StringPrintf("%g", report.max_error) +
      " up to the full test";
  for (const DesignCurve& design : report.study.designs) {
    if (design.n_min < 0) continue;
    n_min_text = StringPrintf("N = %d samples (design %s) keep P(wrong) <= %g", design.n_min,
                              design.name.c_str(), report.max_error);
    if (design.name == "uniform") break;
  }
  const Eigen::Vector2d truth_point(t.x_m, t.y_m);
  const double floor =
      ProbabilityOfWrongLandmark(truth_point, model.noise_part, model.noise_part, landmarks, truth);
  // clang-format off
  return StringPrintf(
      "  Why the report's N_y is so large, and why no N can guarantee the decision:\n"
      "  the report asks each axis alone to resolve the smallest coordinate gap between landmarks, d_min,x = %.2f m\n"
      "  (%s-%s) and d_min,y = %.2f m (%s-%s): 3 sigma below %.2f m and %.2f m per axis. The run's own noise alone\n"
      "  gives the endpoint sigma %.2f m (x) and %.2f m (y) at any N, so neither per-axis requirement can be met by\n"
      "  any number of samples; the report's bound hides this by taking the run's noise as 3 sigma_eta (one sample)\n"
      "  instead of its double integral. In the plane the nearest competitor of %s is %s, %.1f sigma away (noise\n"
      "  part only): the landmarks are far apart, only not along each axis. Judged in 2-D with the honest\n"
      "  covariance, %s; with infinitely many, P(wrong) still stays at %.1e,\n"
      "  the run's noise floor: that is why no N can guarantee the decision.\n",
      // clang-format on
      d_min[0], t.name.c_str(), against[0].c_str(), d_min[1], t.name.c_str(), against[1].c_str(),
      d_min[0] / 2, d_min[1] / 2, std::sqrt(model.noise_part(0, 0)),
      std::sqrt(model.noise_part(1, 1)), t.name.c_str(), nearest_name.c_str(), nearest_2d,
      n_min_text.c_str(), floor);
}

}  // namespace

std::string MinSamplesText(const MinSamplesReport& report) {
  const MinSamplesResult& study = report.study;
  const int full = study.full_samples;
  // clang-format off
  std::string text = StringPrintf(
      "accelcal min_samples: the fewest tilt-test samples that still decide the landmark (truth: %s, the full-data decision)\n"
      "  criterion: P(wrong landmark) <= %g; the refusal \"no landmark is consistent\" happens with probability alpha at any N\n"
      "  endpoint noise part (fixed): sigma %.2f m (x), %.2f m (y); full test N = %d\n\n",
      // clang-format on
      report.landmarks[study.truth].name.c_str(), report.max_error,
      std::sqrt(study.model.noise_part(0, 0)), std::sqrt(study.model.noise_part(1, 1)), full);
  for (size_t d = 0; d < study.designs.size(); ++d) {
    const DesignCurve& design = study.designs[d];
    text += StringPrintf("  design %-8s", design.name.c_str());
    if (design.name == "optimal")
      text += StringPrintf(" (positions %.0f and %.0f deg)", design.theta_a * 180 / M_PI,
                           design.theta_b * 180 / M_PI);
    text += "  N_min = " + SampleCountText(design.n_min, full) +
            "   N_min_3sigma = " + SampleCountText(design.n_min_3sigma, full) + "\n";
    text += "        N    sigma x (m)  sigma y (m)   P(wrong)   landmarks in 3 sigma\n";
    for (const CurvePoint& point : design.curve) {
      const bool near = design.n_min > 0 && point.samples >= design.n_min / 4 &&
                        point.samples <= 4 * design.n_min;
      if (near || point.samples == full) {
        text += StringPrintf("  %7d  %11.2f  %11.2f  %9.2e   %d\n", point.samples,
                             std::sqrt(point.endpoint_covariance(0, 0)),
                             std::sqrt(point.endpoint_covariance(1, 1)), point.p_wrong,
                             point.landmarks_in_3sigma);
      }
    }
    for (const MonteCarloCheck& check : study.checks[d]) text += CheckLine(check);
    text += "\n";
  }
  return text + Explanation(report);
}

nlohmann::json MinSamplesJson(const MinSamplesReport& report) {
  const MinSamplesResult& study = report.study;
  nlohmann::json designs = nlohmann::json::array();
  for (size_t d = 0; d < study.designs.size(); ++d) {
    designs.push_back(DesignJson(study.designs[d], d < study.checks.size()
                                                       ? study.checks[d]
                                                       : std::vector<MonteCarloCheck>()));
  }
  return {{"problem", "min_samples"},
          {"truth", study.truth >= 0 ? nlohmann::json(report.landmarks[study.truth].name)
                                     : nlohmann::json(nullptr)},
          {"max_error", report.max_error},
          {"full_samples", study.full_samples},
          {"designs", designs}};
}

nlohmann::json DesignJson(const DesignCurve& design, const std::vector<MonteCarloCheck>& checks) {
  nlohmann::json curve = nlohmann::json::array();
  for (const CurvePoint& point : design.curve) {
    curve.push_back({{"n", point.samples},
                     {"p_wrong", point.p_wrong},
                     {"sigma_x_m", std::sqrt(point.endpoint_covariance(0, 0))},
                     {"sigma_y_m", std::sqrt(point.endpoint_covariance(1, 1))},
                     {"landmarks_in_3sigma", point.landmarks_in_3sigma}});
  }
  nlohmann::json monte_carlo = nlohmann::json::array();
  for (const MonteCarloCheck& check : checks) {
    monte_carlo.push_back({{"kind", CheckKindName(check.kind)},
                           {"n", check.samples},
                           {"analytic", check.analytic},
                           {"monte_carlo", check.monte_carlo},
                           {"monte_carlo_sd", check.monte_carlo_sd},
                           {"repetitions", check.repetitions}});
  }
  const auto count = [](int n) { return n > 0 ? nlohmann::json(n) : nlohmann::json(nullptr); };
  const bool two_positions = design.name == "optimal";
  return {{"name", design.name},
          {"n_min", count(design.n_min)},
          {"n_min_3sigma", count(design.n_min_3sigma)},
          {"positions_rad", two_positions ? nlohmann::json({design.theta_a, design.theta_b})
                                          : nlohmann::json(nullptr)},
          {"curve", curve},
          {"monte_carlo", monte_carlo}};
}

std::string SampleCountText(int n_min, int limit) {
  return n_min > 0 ? std::to_string(n_min) : "none up to N = " + std::to_string(limit);
}

}  // namespace accelcal
