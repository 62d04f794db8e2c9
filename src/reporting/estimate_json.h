#ifndef ACCELCAL_REPORTING_ESTIMATE_JSON_H_
#define ACCELCAL_REPORTING_ESTIMATE_JSON_H_

// The JSON of the concepts several binaries write, one writer each, so linear_ls,
// trajectory, joint, discover, analyze and the benchmark write them alike:
//
//   a parameter estimate  {"parameters": {name: value}, "stddev": {name: sigma},
//                          "units": {name: unit}, "parameter_order": [name...],
//                          "covariance": [[...]]}
//                         (the covariance in parameter_order, the spec's units)
//   landmark scores       [{"name", "x", "y", "distance_m", "mahalanobis2",
//                           "log_likelihood", "posterior", "p_value"}...]
//   a solution            the estimate, "chi2" {x, y, endpoint (null without a tie to a
//                         landmark)}, "endpoint",
//                         "endpoint_covariance", "endpoint_stddev", "landmarks" and
//                         "reached" (null when no landmark is consistent)

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "estimation/tilt_table/landmark_decision.h"
#include "estimation/tilt_table/parameter_estimate.h"
#include "estimation/tilt_table/trajectory.h"

namespace accelcal {

nlohmann::json ParameterEstimateJson(const ParameterEstimate& estimate);

nlohmann::json LandmarkScoresJson(const LandmarkDecision& decision);

// The decided landmark's name, or null.
nlohmann::json ReachedJson(const LandmarkDecision& decision);

// {name: unit} of the catalogue's parameters among `names` (docs/json.md: beside every
// "parameters" object).
nlohmann::json UnitsJson(const std::vector<std::string>& names);

// The value, or null when it was not computed (docs/json.md: never 0 for "absent").
nlohmann::json OptionalJson(const std::optional<double>& value);

nlohmann::json SolutionJson(const ParameterEstimate& estimate, double chi2_x, double chi2_y,
                            std::optional<double> chi2_endpoint,
                            const DeadReckoningResult& trajectory,
                            const LandmarkDecision& decision);

}  // namespace accelcal

#endif  // ACCELCAL_REPORTING_ESTIMATE_JSON_H_
