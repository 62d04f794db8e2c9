#ifndef ACCELCAL_ESTIMATION_TILT_TABLE_LANDMARK_DECISION_H_
#define ACCELCAL_ESTIMATION_TILT_TABLE_LANDMARK_DECISION_H_

// Which landmark did the vehicle reach? With the endpoint estimate p ~ N(p_true, Sigma)
// and landmark L_k as the hypothesis p_true = L_k:
//
//   d_k^2 = (L_k - p)^T Sigma^-1 (L_k - p)                 (squared Mahalanobis distance)
//   log likelihood_k = -d_k^2/2 - log(2 pi sqrt(det Sigma))
//   posterior_k = exp(-d_k^2/2) / sum_i exp(-d_i^2/2)        (equal priors)
//   p-value_k = P(chi-square(2) > d_k^2) = exp(-d_k^2/2)
//
// The best landmark is the most probable one, but it is reported as reached only when
// it is itself consistent with the endpoint (p-value >= alpha): a posterior near 1 for
// the least bad of several impossible landmarks is not evidence of arrival.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/measurements.h"

namespace accelcal {

struct LandmarkScore {
  Landmark landmark;
  double distance_m = 0.0;
  double mahalanobis2 = 0.0;
  double log_likelihood = 0.0;
  double posterior = 0.0;
  double p_value = 0.0;
};

struct LandmarkDecision {
  std::vector<LandmarkScore> scores;  // in the landmarks' order
  int best = -1;                      // index of the most probable landmark
  double alpha = 0.01;
  bool consistent = false;  // scores[best].p_value >= alpha
  // The reached landmark's name, or empty when none is consistent.
  std::string reached;
};

LandmarkDecision DecideLandmark(const Eigen::Vector2d& endpoint, const Eigen::Matrix2d& covariance,
                                const std::vector<Landmark>& landmarks, double alpha);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TILT_TABLE_LANDMARK_DECISION_H_
