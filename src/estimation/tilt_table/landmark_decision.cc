#include "estimation/tilt_table/landmark_decision.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace accelcal {

LandmarkDecision DecideLandmark(const Eigen::Vector2d& endpoint, const Eigen::Matrix2d& covariance,
                                const std::vector<Landmark>& landmarks, double alpha) {
  LandmarkDecision decision;
  decision.alpha = alpha;
  const Eigen::LLT<Eigen::Matrix2d> cholesky(covariance);
  const double log_normalizer = std::log(2.0 * M_PI) + 0.5 * std::log(covariance.determinant());
  double max_log_likelihood = -HUGE_VAL;
  for (const Landmark& landmark : landmarks) {
    LandmarkScore score;
    score.landmark = landmark;
    const Eigen::Vector2d difference = Eigen::Vector2d(landmark.x_m, landmark.y_m) - endpoint;
    score.distance_m = difference.norm();
    score.mahalanobis2 = difference.dot(cholesky.solve(difference));
    score.log_likelihood = -0.5 * score.mahalanobis2 - log_normalizer;
    score.p_value = std::exp(-0.5 * score.mahalanobis2);
    max_log_likelihood = std::max(max_log_likelihood, score.log_likelihood);
    decision.scores.push_back(score);
  }
  // Posteriors by log-sum-exp, so that far landmarks do not underflow to 0/0.
  double sum = 0.0;
  for (const LandmarkScore& score : decision.scores)
    sum += std::exp(score.log_likelihood - max_log_likelihood);
  for (size_t k = 0; k < decision.scores.size(); ++k) {
    LandmarkScore& score = decision.scores[k];
    score.posterior = std::exp(score.log_likelihood - max_log_likelihood) / sum;
    if (decision.best < 0 || score.posterior > decision.scores[decision.best].posterior) {
      decision.best = static_cast<int>(k);
    }
  }
  if (decision.best >= 0) {
    decision.consistent = decision.scores[decision.best].p_value >= alpha;
    if (decision.consistent) decision.reached = decision.scores[decision.best].landmark.name;
  }
  return decision;
}

}  // namespace accelcal
