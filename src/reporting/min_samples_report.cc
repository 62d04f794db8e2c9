#include "reporting/min_samples_report.h"

#include <cmath>

namespace accelcal {

nlohmann::json DesignJson(const DesignCurve& design, const nlohmann::json& monte_carlo_checks) {
  nlohmann::json curve = nlohmann::json::array();
  for (const CurvePoint& point : design.curve) {
    curve.push_back({{"n", point.samples},
                     {"p_wrong", point.p_wrong},
                     {"sigma_x_m", std::sqrt(point.endpoint_covariance(0, 0))},
                     {"sigma_y_m", std::sqrt(point.endpoint_covariance(1, 1))},
                     {"landmarks_in_3sigma", point.landmarks_in_3sigma}});
  }
  return {{"name", design.name},
          {"n_min", design.n_min},
          {"n_min_3sigma", design.n_min_3sigma},
          {"positions_rad", {design.theta_a, design.theta_b}},
          {"curve", curve},
          {"monte_carlo", monte_carlo_checks}};
}

std::string SampleCountText(int n_min, int limit) {
  return n_min > 0 ? std::to_string(n_min) : "none up to N = " + std::to_string(limit);
}

}  // namespace accelcal
