#include "reporting/estimate_json.h"

#include <cmath>

namespace accelcal {

nlohmann::json ParameterEstimateJson(const ParameterEstimate& estimate) {
  nlohmann::json parameters = nlohmann::json::object();
  nlohmann::json stddev = nlohmann::json::object();
  nlohmann::json units = nlohmann::json::object();
  nlohmann::json order = nlohmann::json::array();
  for (const Parameter parameter : estimate.free) {
    parameters[Info(parameter).name] = estimate.Value(parameter);
    stddev[Info(parameter).name] = estimate.StandardDeviation(parameter);
    units[Info(parameter).name] = Info(parameter).unit;
    order.push_back(Info(parameter).name);
  }
  nlohmann::json covariance = nlohmann::json::array();
  for (int r = 0; r < estimate.covariance.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int c = 0; c < estimate.covariance.cols(); ++c) row.push_back(estimate.covariance(r, c));
    covariance.push_back(row);
  }
  return {{"parameters", parameters},
          {"stddev", stddev},
          {"units", units},
          {"parameter_order", order},
          {"covariance", covariance}};
}

nlohmann::json LandmarkScoresJson(const LandmarkDecision& decision) {
  nlohmann::json landmarks = nlohmann::json::array();
  for (const LandmarkScore& score : decision.scores) {
    landmarks.push_back({{"name", score.landmark.name},
                         {"x", score.landmark.x_m},
                         {"y", score.landmark.y_m},
                         {"distance_m", score.distance_m},
                         {"mahalanobis2", score.mahalanobis2},
                         {"log_likelihood", score.log_likelihood},
                         {"posterior", score.posterior},
                         {"p_value", score.p_value}});
  }
  return landmarks;
}

nlohmann::json ReachedJson(const LandmarkDecision& decision) {
  return decision.reached.empty() ? nlohmann::json(nullptr) : nlohmann::json(decision.reached);
}

nlohmann::json UnitsJson(const std::vector<std::string>& names) {
  nlohmann::json units = nlohmann::json::object();
  for (const std::string& name : names) {
    if (const ParameterInfo* info = FindParameter(name)) units[name] = info->unit;
  }
  return units;
}

nlohmann::json OptionalJson(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

nlohmann::json SolutionJson(const ParameterEstimate& estimate, double chi2_x, double chi2_y,
                            std::optional<double> chi2_endpoint,
                            const DeadReckoningResult& trajectory,
                            const LandmarkDecision& decision) {
  const Eigen::Matrix2d& c = trajectory.covariance;
  nlohmann::json json = ParameterEstimateJson(estimate);
  json["chi2"] = {{"x", chi2_x}, {"y", chi2_y}, {"endpoint", OptionalJson(chi2_endpoint)}};
  json["endpoint"] = {{"x", trajectory.endpoint.x()}, {"y", trajectory.endpoint.y()}};
  json["endpoint_covariance"] = {{c(0, 0), c(0, 1)}, {c(1, 0), c(1, 1)}};
  json["endpoint_stddev"] = {{"x", std::sqrt(c(0, 0))}, {"y", std::sqrt(c(1, 1))}};
  json["landmarks"] = LandmarkScoresJson(decision);
  json["reached"] = ReachedJson(decision);
  return json;
}

}  // namespace accelcal
