#include "studies/min_samples.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include "estimation/tilt_table/baseline_parameters.h"
#include "estimation/tilt_table/landmark_decision.h"
#include "estimation/tilt_table/linear_ls.h"
#include "models/tilt_table.h"
#include "simulation/monte_carlo.h"
#include "simulation/random.h"
#include "simulation/simulator.h"

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

namespace accelcal {

const std::vector<std::string>& DesignNames() {
  static const std::vector<std::string> names = {"uniform", "four", "two", "optimal"};
  return names;
}

EndpointModel EndpointModelOf(const DeadReckoningResult& trajectory, double gravity_mps2,
                              double noise_variance_x, double noise_variance_y) {
  EndpointModel model;
  model.jacobian = trajectory.jacobian;
  model.noise_part = trajectory.noise_part;
  model.endpoint = trajectory.endpoint;
  model.gravity_mps2 = gravity_mps2;
  model.noise_variance_x = noise_variance_x;
  model.noise_variance_y = noise_variance_y;
  return model;
}

Status BuildEndpointModel(const CalibrationTest& test, const VehicleRun& run,
                          const RunConditions& conditions, const std::vector<Landmark>& landmarks,
                          double gravity_mps2, EndpointModel* model, int* truth) {
  const LinearLsOptions options = LinearLsOptionsFor(conditions, gravity_mps2);
  BaselineFit fit;
  ACCELCAL_RETURN_IF_ERROR(EstimateLinearLs(test, options, &fit));
  TrajectoryOptions trajectory_options;
  trajectory_options.path_stride = run.size();
  DeadReckoningResult trajectory;
  ACCELCAL_RETURN_IF_ERROR(DeadReckon(run, conditions, fit, trajectory_options, &trajectory));
  *model = EndpointModelOf(trajectory, gravity_mps2, conditions.noise_variance_x,
                           conditions.noise_variance_y);
  // Only the most probable landmark is used, which does not depend on alpha.
  *truth = DecideLandmark(trajectory.endpoint, trajectory.covariance, landmarks, 0.01).best;
  return Status::Ok();
}

std::vector<DesignCurve> AnalyseDesigns(const EndpointModel& model,
                                        const std::vector<Landmark>& landmarks, int truth,
                                        const std::vector<std::string>& names, double max_error,
                                        int max_samples, int* uniform_n_min) {
  *uniform_n_min = kDefaultReferenceSamples;
  std::vector<DesignCurve> designs;
  for (const std::string& name : names) {
    DesignCurve design;
    design.name = name;
    if (name == "optimal") {
      design = OptimalTwoPositionDesign(
          model, landmarks, truth, *uniform_n_min > 0 ? *uniform_n_min : kDefaultReferenceSamples);
    }
    design = AnalyseDesign(model, landmarks, truth, design, max_error, max_samples);
    if (name == "uniform") *uniform_n_min = design.n_min;
    designs.push_back(design);
  }
  return designs;
}

namespace {

// Wrong-decision rate of `trials` fits of a test made by `make_test(trial)` with the run made
// by `make_run(trial)`; a test that cannot be fitted counts against its design.
double MonteCarloWrongRate(const std::function<CalibrationTest(int)>& make_test,
                           const std::function<VehicleRun(int)>& make_run,
                           const RunConditions& conditions, const std::vector<Landmark>& landmarks,
                           int truth, int trials, const MinSamplesOptions& options,
                           ProgressCounter* progress) {
  std::vector<int> wrong(trials, 0);
  MonteCarloOptions monte_carlo;
  monte_carlo.trials = trials;
  monte_carlo.threads = options.threads;
  monte_carlo.progress = progress;
  RunTrials(monte_carlo, [&](int trial) {
    EndpointModel model;
    int decided = -1;
    if (!BuildEndpointModel(make_test(trial), make_run(trial), conditions, landmarks,
                            options.gravity_mps2, &model, &decided)
             .ok()) {
      wrong[trial] = 1;
      return;
    }
    wrong[trial] = decided != truth;
  });
  return std::count(wrong.begin(), wrong.end(), 1) / static_cast<double>(trials);
}

// The N a design is checked at: a quarter of N_min (at least 10) and N_min.
constexpr int kCheckedSampleCounts = 2;
std::array<int, kCheckedSampleCounts> CheckedSampleCounts(const DesignCurve& design) {
  return {std::max(10, design.n_min / 4), design.n_min};
}

// Full simulation of test and run from the scenario, at and below N_min.
Status FullSimulationChecks(const Scenario& scenario, const DesignCurve& design,
                            const MinSamplesOptions& options, ProgressCounter* progress,
                            std::vector<MonteCarloCheck>* checks) {
  const SimulatedData reference = SimulateScenario(scenario, options.seed, 1u << 30);
  EndpointModel model;
  int decided = -1;
  ACCELCAL_RETURN_IF_ERROR(BuildEndpointModel(reference.test, reference.run, reference.conditions,
                                              reference.landmarks, options.gravity_mps2, &model,
                                              &decided)
                               .WithContext("the simulated reference of the Monte Carlo check"));
  int true_index = 0;
  for (size_t k = 0; k < reference.landmarks.size(); ++k) {
    if (reference.landmarks[k].name == reference.reached_landmark) true_index = static_cast<int>(k);
  }
  for (const int n : CheckedSampleCounts(design)) {
    MonteCarloCheck check;
    check.kind = MonteCarloCheck::Kind::kFullSimulation;
    check.samples = n;
    check.analytic = EvaluateDesign(model, reference.landmarks, true_index, design, n).p_wrong;
    check.monte_carlo = MonteCarloWrongRate(
        [&](int trial) {
          TiltSchedule schedule;
          schedule.kind = TiltSchedule::Kind::kList;
          schedule.angles_rad = DesignAngles(design.name, n, design.theta_a, design.theta_b);
          return SimulateTiltTest(schedule, scenario.truth, options.seed + 7, trial);
        },
        [&](int trial) {
          std::vector<double> t;
          std::vector<double> ax;
          std::vector<double> ay;
          TrueRunAcceleration(scenario.run, &t, &ax, &ay);
          return SimulateVehicleRun(t, ax, ay, scenario.truth, options.seed + 7, trial);
        },
        reference.conditions, reference.landmarks, true_index, options.repetitions, options,
        progress);
    check.repetitions = options.repetitions;
    check.independent = options.repetitions;
    check.monte_carlo_sd =
        std::sqrt(std::max(check.analytic * (1 - check.analytic), 1e-12) / check.independent);
    checks->push_back(check);
  }
  return Status::Ok();
}

// The real test's own subsets: the real run's noise is one fixed realisation, so only the
// parameters vary: the estimate is centred on the full-data endpoint with covariance
// J Sigma_N J^T (1 - N / N_full).
void RealTestSubsetChecks(const CalibrationTest& test, const VehicleRun& run,
                          const RunConditions& conditions, const std::vector<Landmark>& landmarks,
                          const MinSamplesResult& study, const DesignCurve& design,
                          const MinSamplesOptions& options, ProgressCounter* progress,
                          std::vector<MonteCarloCheck>* checks) {
  const EndpointModel& model = study.model;
  const int full = study.full_samples;
  for (const int n : CheckedSampleCounts(design)) {
    const std::vector<double> angles = DesignAngles("uniform", n);
    const Eigen::Matrix4d parameters = BaselineCovarianceForDesign(
        angles, model.gravity_mps2, model.noise_variance_x, model.noise_variance_y);
    const Eigen::Matrix2d spread =
        model.jacobian * parameters * model.jacobian.transpose() * (1.0 - double(n) / full);
    const Eigen::Matrix2d decision =
        model.jacobian * parameters * model.jacobian.transpose() + model.noise_part;
    const double analytic =
        ProbabilityOfWrongLandmark(model.endpoint, spread, decision, landmarks, study.truth);
    // Random subsets, and evenly spaced ones (every full/N-th sample from a random offset).
    for (const bool evenly : {false, true}) {
      MonteCarloCheck check;
      check.kind = evenly ? MonteCarloCheck::Kind::kRealTestEvenSubsets
                          : MonteCarloCheck::Kind::kRealTestSubsets;
      check.samples = n;
      check.analytic = analytic;
      check.monte_carlo = MonteCarloWrongRate(
          [&](int trial) {
            RandomSource random(options.seed + (evenly ? 13 : 11), trial);
            std::vector<int> chosen;
            if (evenly) {
              const double stride = static_cast<double>(full) / n;
              const double offset = random.Uniform() * stride;
              for (int i = 0; i < n; ++i)
                chosen.push_back(std::min(full - 1, static_cast<int>(offset + i * stride)));
            } else {
              std::vector<int> order(full);
              for (int i = 0; i < full; ++i) order[i] = i;
              for (int i = 0; i < n; ++i)
                std::swap(order[i], order[i + static_cast<int>(random.Uniform() * (full - i))]);
              chosen.assign(order.begin(), order.begin() + n);
              std::sort(chosen.begin(), chosen.end());
            }
            CalibrationTest subset;
            for (const int i : chosen) {
              subset.theta_rad.push_back(test.theta_rad[i]);
              subset.measured_x.push_back(test.measured_x[i]);
              subset.measured_y.push_back(test.measured_y[i]);
            }
            return subset;
          },
          [&](int) { return run; }, conditions, landmarks, study.truth, options.repetitions,
          options, progress);
      check.repetitions = options.repetitions;
      // Evenly spaced subsets of the real test are at most full/N disjoint ones: the
      // repetitions draw from that many independent outcomes, not from `repetitions`.
      check.independent = evenly ? std::min(options.repetitions, full / n) : options.repetitions;
      check.monte_carlo_sd =
          std::sqrt(std::max(analytic * (1 - analytic), 1e-12) / check.independent);
      checks->push_back(check);
    }
  }
}

// Which checks a design gets: none without repetitions or without an N_min; the uniform
// design also the real test's subsets, random and evenly spaced, when asked for.
bool IsChecked(const DesignCurve& design, const MinSamplesOptions& options) {
  return options.repetitions > 0 && design.n_min > 0;
}
bool ChecksSubsets(const DesignCurve& design, const MinSamplesOptions& options) {
  return IsChecked(design, options) && design.name == "uniform" && options.subset_checks;
}

// The Monte Carlo trials of every check, for the progress: each kind of check runs
// options.repetitions at each of CheckedSampleCounts.
int64_t CheckTrials(const std::vector<DesignCurve>& designs, const MinSamplesOptions& options) {
  int64_t kinds = 0;
  for (const DesignCurve& design : designs) {
    kinds += IsChecked(design, options) ? 1 : 0;      // full simulation
    kinds += ChecksSubsets(design, options) ? 2 : 0;  // random and evenly spaced subsets
  }
  return kinds * kCheckedSampleCounts * options.repetitions;
}

}  // namespace

Status RunMinSamplesStudy(const CalibrationTest& test, const VehicleRun& run,
                          const RunConditions& conditions, const std::vector<Landmark>& landmarks,
                          const Scenario& scenario, const MinSamplesOptions& options,
                          MinSamplesResult* result) {
  ACCELCAL_RETURN_IF_ERROR(BuildEndpointModel(
      test, run, conditions, landmarks, options.gravity_mps2, &result->model, &result->truth));
  if (landmarks.size() < 2 || result->truth < 0) {
    return Status::Error("need at least two landmarks");
  }
  result->full_samples = test.size();
  result->designs = AnalyseDesigns(result->model, landmarks, result->truth, options.designs,
                                   options.max_error, result->full_samples, &result->uniform_n_min);
  result->checks.assign(result->designs.size(), {});
  ProgressCounter progress(options.progress, CheckTrials(result->designs, options));
  for (size_t d = 0; d < result->designs.size(); ++d) {
    const DesignCurve& design = result->designs[d];
    if (!IsChecked(design, options)) continue;
    ACCELCAL_RETURN_IF_ERROR(
        FullSimulationChecks(scenario, design, options, &progress, &result->checks[d]));
    if (ChecksSubsets(design, options)) {
      RealTestSubsetChecks(test, run, conditions, landmarks, *result, design, options, &progress,
                           &result->checks[d]);
    }
  }
  return Status::Ok();
}

}  // namespace accelcal
