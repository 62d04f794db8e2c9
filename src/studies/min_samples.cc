#include "studies/min_samples.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "estimation/baseline_parameters.h"
#include "estimation/linear_ls.h"
#include "models/tilt_table.h"

namespace accelcal {

std::vector<double> DesignAngles(const std::string& design, int samples, double theta_a,
                                 double theta_b) {
  std::vector<double> angles;
  auto positions = [&](const std::vector<double>& where) {
    for (size_t p = 0; p < where.size(); ++p) {
      const int begin = static_cast<int>(static_cast<long long>(p) * samples / where.size());
      const int end = static_cast<int>(static_cast<long long>(p + 1) * samples / where.size());
      angles.insert(angles.end(), end - begin, where[p]);
    }
  };
  if (design == "uniform") {
    for (int i = 0; i < samples; ++i) angles.push_back(2.0 * M_PI * i / std::max(1, samples - 1));
  } else if (design == "four") {
    positions({0.0, 0.5 * M_PI, M_PI, 1.5 * M_PI});
  } else if (design == "two") {
    positions({0.25 * M_PI, 1.25 * M_PI});
  } else {
    positions({theta_a, theta_b});
  }
  return angles;
}

Eigen::Matrix4d BaselineCovarianceForDesign(const std::vector<double>& theta_rad,
                                            double gravity_mps2, double noise_variance_x,
                                            double noise_variance_y) {
  // The closed form's own sufficient statistics (the measured values do not matter for
  // the covariance): the same code that estimates, so the design's covariance is exactly
  // the one the estimator would report.
  CalibrationAccumulator statistics(gravity_mps2);
  for (double theta : theta_rad) statistics.Add(theta, 0.0, 0.0);
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
  const std::array<const AxisRegressionAccumulator*, 2> axes = {&statistics.x(), &statistics.y()};
  const std::array<double, 2> variances = {noise_variance_x, noise_variance_y};
  for (int k = 0; k < 2; ++k) {
    const double n = static_cast<double>(axes[k]->count());
    const double centered = axes[k]->CenteredForceForce();
    const double mean = axes[k]->MeanForce();
    const int b = BaselineIndex(BiasOf(k));
    const int s = BaselineIndex(ScaleOf(k));
    if (!(centered > 0.0)) {
      covariance(b, b) = covariance(s, s) = 1e30;  // not separable
      continue;
    }
    covariance(b, b) = variances[k] * (1.0 / n + mean * mean / centered);
    covariance(b, s) = covariance(s, b) = -variances[k] * mean / centered;
    covariance(s, s) = variances[k] / centered;
  }
  return covariance;
}

namespace {

// Keeps only the half-planes normal . z <= margin (margin > 0) that can bound the cell. In
// the polar dual each is the point normal / margin, and a half-plane can be active only when
// its point is a vertex of the convex hull of all of them; the others are implied. This makes
// a cell of n landmarks cost O(n log n) once instead of O(n) per quadrature direction (2,000
// landmarks: the radius loop had 1.4 million terms per evaluation).
void PruneRedundantHalfPlanes(std::vector<Eigen::Vector2d>* normals, std::vector<double>* margins) {
  const size_t count = normals->size();
  if (count <= 3) return;
  std::vector<size_t> order(count);
  std::vector<Eigen::Vector2d> dual(count);
  for (size_t k = 0; k < count; ++k) {
    order[k] = k;
    dual[k] = (*normals)[k] / (*margins)[k];
  }
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return dual[a].x() < dual[b].x() || (dual[a].x() == dual[b].x() && dual[a].y() < dual[b].y());
  });
  auto cross = [&](size_t o, size_t a, size_t b) {
    return (dual[a] - dual[o]).x() * (dual[b] - dual[o]).y() -
           (dual[a] - dual[o]).y() * (dual[b] - dual[o]).x();
  };
  // Andrew's monotone chain; collinear points are kept (the strict test), since a point on
  // an edge may still be the active constraint in one direction when ties are exact.
  std::vector<size_t> hull(2 * count);
  size_t size = 0;
  for (size_t i = 0; i < count; ++i) {
    while (size >= 2 && cross(hull[size - 2], hull[size - 1], order[i]) < 0.0) --size;
    hull[size++] = order[i];
  }
  for (size_t i = count - 1, lower = size + 1; i-- > 0;) {
    while (size >= lower && cross(hull[size - 2], hull[size - 1], order[i]) < 0.0) --size;
    hull[size++] = order[i];
  }
  std::vector<bool> keep(count, false);
  for (size_t i = 0; i < size; ++i) keep[hull[i]] = true;
  std::vector<Eigen::Vector2d> kept_normals;
  std::vector<double> kept_margins;
  for (size_t k = 0; k < count; ++k) {
    if (!keep[k]) continue;
    kept_normals.push_back((*normals)[k]);
    kept_margins.push_back((*margins)[k]);
  }
  *normals = std::move(kept_normals);
  *margins = std::move(kept_margins);
}

}  // namespace

double ProbabilityOfWrongLandmark(const Eigen::Vector2d& center,
                                  const Eigen::Matrix2d& distribution_covariance,
                                  const Eigen::Matrix2d& decision_covariance,
                                  const std::vector<Landmark>& landmarks, int truth,
                                  int quadrature_points) {
  // Decision cell of `truth`: points p with (p - L_t)^T M (p - L_t) <= (p - L_k)^T M (p - L_k)
  // for every k, M = decision_covariance^-1: the half-planes a_k^T p <= c_k with
  // a_k = 2 M (L_k - L_t), c_k = L_k^T M L_k - L_t^T M L_t.
  const Eigen::Matrix2d metric = decision_covariance.inverse();
  const Eigen::Vector2d truth_point(landmarks[truth].x_m, landmarks[truth].y_m);
  // Whiten the distribution: p = center + S z, z ~ N(0, I).
  const Eigen::Matrix2d root = distribution_covariance.llt().matrixL();
  std::vector<Eigen::Vector2d> normals;
  std::vector<double> margins;  // distance from z = 0 along the normal direction
  for (size_t k = 0; k < landmarks.size(); ++k) {
    if (static_cast<int>(k) == truth) continue;
    const Eigen::Vector2d other(landmarks[k].x_m, landmarks[k].y_m);
    const Eigen::Vector2d a = 2.0 * metric * (other - truth_point);
    const double c = other.dot(metric * other) - truth_point.dot(metric * truth_point);
    // In z: (S^T a)^T z <= c - a^T center.
    const Eigen::Vector2d normal = root.transpose() * a;
    const double slack = c - a.dot(center);
    if (slack <= 0.0) return 1.0;  // the centre itself is decided wrongly
    normals.push_back(normal / normal.norm());
    margins.push_back(slack / normal.norm());
  }
  PruneRedundantHalfPlanes(&normals, &margins);
  double sum = 0.0;
  for (int q = 0; q < quadrature_points; ++q) {
    const double phi = 2.0 * M_PI * (q + 0.5) / quadrature_points;
    const Eigen::Vector2d direction(std::cos(phi), std::sin(phi));
    double radius = HUGE_VAL;
    for (size_t k = 0; k < normals.size(); ++k) {
      const double along = direction.dot(normals[k]);
      if (along > 0.0) radius = std::min(radius, margins[k] / along);
    }
    if (std::isfinite(radius)) sum += std::exp(-0.5 * radius * radius);
  }
  return sum / quadrature_points;
}

CurvePoint EvaluateDesign(const EndpointModel& model, const std::vector<Landmark>& landmarks,
                          int truth, const DesignCurve& design, int samples) {
  CurvePoint point;
  point.samples = samples;
  const std::vector<double> angles =
      DesignAngles(design.name, samples, design.theta_a, design.theta_b);
  const Eigen::Matrix4d parameters = BaselineCovarianceForDesign(
      angles, model.gravity_mps2, model.noise_variance_x, model.noise_variance_y);
  point.endpoint_covariance =
      model.jacobian * parameters * model.jacobian.transpose() + model.noise_part;
  const Eigen::Vector2d truth_point(landmarks[truth].x_m, landmarks[truth].y_m);
  point.p_wrong = ProbabilityOfWrongLandmark(truth_point, point.endpoint_covariance,
                                             point.endpoint_covariance, landmarks, truth);
  const Eigen::Matrix2d inverse = point.endpoint_covariance.inverse();
  for (const Landmark& landmark : landmarks) {
    const Eigen::Vector2d d = Eigen::Vector2d(landmark.x_m, landmark.y_m) - model.endpoint;
    point.landmarks_in_3sigma += d.dot(inverse * d) <= 9.0;
  }
  return point;
}

namespace {

// Smallest N in [low, high] with predicate true, for a predicate false then true in N.
template <typename Predicate>
int SmallestSamples(int low, int high, Predicate predicate) {
  if (!predicate(high)) return -1;
  if (predicate(low)) return low;
  while (high - low > 1) {
    const int middle = low + (high - low) / 2;
    (predicate(middle) ? high : low) = middle;
  }
  return high;
}

}  // namespace

DesignCurve AnalyseDesign(const EndpointModel& model, const std::vector<Landmark>& landmarks,
                          int truth, const DesignCurve& design_in, double max_error,
                          int max_samples) {
  DesignCurve design = design_in;
  design.curve.clear();
  constexpr int kSmallest = 10;
  for (double n = kSmallest; n < max_samples; n *= 1.25) {
    design.curve.push_back(
        EvaluateDesign(model, landmarks, truth, design, static_cast<int>(std::lround(n))));
  }
  design.curve.push_back(EvaluateDesign(model, landmarks, truth, design, max_samples));
  design.n_min = SmallestSamples(kSmallest, max_samples, [&](int n) {
    return EvaluateDesign(model, landmarks, truth, design, n).p_wrong <= max_error;
  });
  design.n_min_3sigma = SmallestSamples(kSmallest, max_samples, [&](int n) {
    return EvaluateDesign(model, landmarks, truth, design, n).landmarks_in_3sigma == 1;
  });
  return design;
}

DesignCurve OptimalTwoPositionDesign(const EndpointModel& model,
                                     const std::vector<Landmark>& landmarks, int truth,
                                     int reference_samples) {
  DesignCurve best;
  best.name = "optimal";
  double best_p = HUGE_VAL;
  DesignCurve candidate;
  candidate.name = "positions";
  for (int a = 0; a < 72; ++a) {
    for (int b = a + 1; b < 72; ++b) {
      candidate.theta_a = a * M_PI / 36.0;
      candidate.theta_b = b * M_PI / 36.0;
      const std::vector<double> angles =
          DesignAngles("positions", reference_samples, candidate.theta_a, candidate.theta_b);
      const Eigen::Matrix4d parameters = BaselineCovarianceForDesign(
          angles, model.gravity_mps2, model.noise_variance_x, model.noise_variance_y);
      if (parameters(BaselineIndex(Parameter::kBiasX), BaselineIndex(Parameter::kBiasX)) > 1e20 ||
          parameters(BaselineIndex(Parameter::kBiasY), BaselineIndex(Parameter::kBiasY)) > 1e20)
        continue;
      const Eigen::Matrix2d covariance =
          model.jacobian * parameters * model.jacobian.transpose() + model.noise_part;
      const Eigen::Vector2d truth_point(landmarks[truth].x_m, landmarks[truth].y_m);
      const double p =
          ProbabilityOfWrongLandmark(truth_point, covariance, covariance, landmarks, truth, 720);
      if (p < best_p) {
        best_p = p;
        best.theta_a = candidate.theta_a;
        best.theta_b = candidate.theta_b;
      }
    }
  }
  return best;
}

}  // namespace accelcal
