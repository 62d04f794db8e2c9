#include "estimation/triad/triad_pose_noise.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include "common/format.h"
#include "common/statistics.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/triad/noise_floor_detector.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "residuals/triad_pose_residual.h"

namespace accelcal {

Status TriadPoseNoiseFromLog(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                             const std::vector<TriadPoseMean>& poses, TriadPoseNoise* noise) {
  *noise = TriadPoseNoise();
  if (intervals.size() != poses.size() || poses.empty())
    return Status::Error("the coloured noise model needs one interval per pose");
  if (log.size() < 2) return Status::Error("the log is too short for an Allan variance");
  const double sample_period_s =
      (log.timestamp_s.back() - log.timestamp_s.front()) / static_cast<double>(log.size() - 1);
  std::vector<double> durations;
  for (const TriadPoseMean& pose : poses) durations.push_back(pose.duration_s);
  const double median_duration_s = UpperMedian(durations);
  const std::array<double, 3> white = PooledWithinPoseVariance(poses);

  double smallest_p = 1.0;
  for (int k = 0; k < 3; ++k) {
    std::vector<std::vector<double>> segments;
    for (const StaticInterval& interval : intervals) {
      std::vector<double> samples;
      for (int i = interval.start; i <= interval.end; ++i) samples.push_back(log.output[i][k]);
      segments.push_back(std::move(samples));
    }
    AllanOptions options;
    AllanCurve curve;
    ACCELCAL_RETURN_IF_ERROR(ComputeAllanVariance(segments, sample_period_s, options, &curve)
                                 .WithContext(StringPrintf("axis %c's poses", "xyz"[k])));
    // The test point before the fit: the fit fills each point's edf by the noise it finds.
    int test = -1;
    for (size_t i = 0; i < curve.points.size(); ++i)
      if (curve.points[i].tau_s <= 0.5 * median_duration_s) test = static_cast<int>(i);
    if (test < 0) {
      return Status::Error(StringPrintf(
          "the poses (median %.3g s) are too short for the Allan variance of their noise",
          median_duration_s));
    }
    const AllanPoint point = curve.points[test];
    // The segments the point averages, and only those: a short pose does not enter a long
    // tau's point, and counting it would make the test overconfident.
    const double edf = AllanCurveDof(AllanNoiseKind::kWhite, curve, point.cluster_samples);
    const double expected = white[k] / static_cast<double>(point.cluster_samples);
    noise->test_tau_s = point.tau_s;
    noise->avar_ratio[k] = point.avar / expected;
    noise->white_p_value[k] = ChiSquareSurvival(edf * noise->avar_ratio[k], edf);
    smallest_p = std::min(smallest_p, noise->white_p_value[k]);

    AllanNoiseFit fit;
    ACCELCAL_RETURN_IF_ERROR(FitAllanNoise(options, &curve, &fit)
                                 .WithContext(StringPrintf("axis %c's poses", "xyz"[k])));
    noise->terms[k] = FittedNoiseTerms(fit);
  }
  TriadNoiseCandidate& candidate = noise->candidate;
  candidate.white_p_value = std::min(1.0, 3.0 * smallest_p);
  for (const TriadPoseMean& pose : poses) {
    std::array<double, 3> variance;
    for (int k = 0; k < 3; ++k) {
      variance[k] =
          AllanPoseMeanVariance(noise->terms[k], std::max(pose.duration_s, sample_period_s));
      // Never below what white noise of the pose's own samples gives.
      variance[k] = std::max(variance[k], white[k] / pose.sample_count);
    }
    candidate.pose_mean_variance.push_back(variance);
  }
  candidate.correlation = TriadPoseCorrelationFromTerms(noise->terms, poses, white);
  candidate.description = StringPrintf(
      "Allan variance of the poses' samples (terms N, B, K fitted per axis; a pose mean of T s "
      "has variance sigma^2(T)); at tau = %.3g s it is (%.3g, %.3g, %.3g) times white noise's",
      noise->test_tau_s, noise->avar_ratio[0], noise->avar_ratio[1], noise->avar_ratio[2]);
  const TriadPoseCorrelation& correlation = candidate.correlation;
  if (!correlation.empty()) {
    candidate.description += StringPrintf(
        "; the pose means are judged correlated across poses by the bias instability (B = "
        "%.3g, %.3g, %.3g) as flicker noise, %zu Gauss-Markov processes at %.3g to %.3g s",
        noise->terms[0].bias_instability, noise->terms[1].bias_instability,
        noise->terms[2].bias_instability, correlation.correlation_s.size(),
        correlation.correlation_s.front(), correlation.correlation_s.back());
  }
  return Status::Ok();
}

namespace {

constexpr double kFlickerAllanFloor = 0.441;  // 2 ln 2 / pi: flicker's Allan variance over B^2
constexpr double kBankSpacing = 4.0;

// One Gauss-Markov process's Allan variance at tau over its variance (correlation time T).
double MarkovAllanVariance(double tau_s, double correlation_s) {
  const double x = tau_s / correlation_s;
  if (x < 1e-4) return 2.0 * x / 3.0 - 0.5 * x * x;
  return (2.0 * x - 3.0 + 4.0 * std::exp(-x) - std::exp(-2.0 * x)) / (x * x);
}

// The variance of a window's mean of a unit process with x = window / correlation time, and
// the factor b of its covariance with another window's (header).
double WindowVariance(double x) {
  if (x < 1e-4) return 1.0 - x / 3.0;
  return 2.0 * (x - 1.0 + std::exp(-x)) / (x * x);
}
double WindowFactor(double x) {
  if (x < 1e-4) return 1.0 + x * x / 24.0;
  return std::sinh(0.5 * x) / (0.5 * x);
}

// The independent part of pose p's mean variance on axis k (header): the white and random-walk
// terms; never below s^2 / N_p.
double IndependentVariance(const TriadPoseCorrelation& model, const TriadPoseMean& pose, int k) {
  const double t = std::max(pose.duration_s, 1e-9);
  const double n = model.white_density[k];
  const double r = model.random_walk[k];
  return std::max(n * n / t + r * r * t / 3.0,
                  model.sample_variance[k] / std::max(pose.sample_count, 1));
}

}  // namespace

TriadPoseCorrelation TriadPoseCorrelationFromTerms(const std::array<AllanNoiseTerms, 3>& terms,
                                                   const std::vector<TriadPoseMean>& poses,
                                                   const std::array<double, 3>& sample_variance) {
  TriadPoseCorrelation model;
  bool any = false;
  for (const AllanNoiseTerms& axis : terms) any = any || axis.bias_instability > 0.0;
  if (!any || poses.size() < 2) return model;
  std::vector<double> durations;
  double first_s = poses.front().time_s;
  double last_s = first_s;
  for (const TriadPoseMean& pose : poses) {
    durations.push_back(pose.duration_s);
    first_s = std::min(first_s, pose.time_s);
    last_s = std::max(last_s, pose.time_s);
  }
  const double shortest_s = std::max(0.25 * UpperMedian(durations), 1e-3);
  const double span_s = std::max(last_s - first_s, shortest_s);
  for (double t = shortest_s;; t *= kBankSpacing) {
    model.correlation_s.push_back(t);
    if (t >= span_s && model.correlation_s.size() >= 2) break;
  }
  const double reference_s = std::sqrt(model.correlation_s.front() * model.correlation_s.back());
  double unit_allan = 0.0;
  for (const double t : model.correlation_s) unit_allan += MarkovAllanVariance(reference_s, t);
  for (int k = 0; k < 3; ++k) {
    const double b = terms[k].bias_instability;
    model.process_variance[k] = kFlickerAllanFloor * b * b / unit_allan;
    model.white_density[k] = terms[k].white_density;
    model.random_walk[k] = terms[k].random_walk;
    model.sample_variance[k] = sample_variance[k];
  }
  return model;
}

Status TriadCorrelatedChi2(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                           const TriadPoseCorrelation& correlation,
                           const std::array<double, 3>& added_variance, double gravity_mps2,
                           double* chi2, std::vector<double>* innovations) {
  const int pose_count = static_cast<int>(poses.size());
  if (correlation.empty()) return Status::Error("no correlation model of the pose means");
  if (static_cast<int>(fit.directions.size()) != pose_count)
    return Status::Error("the fit is not of these poses");
  const std::vector<int>& estimated = fit.effects_estimated;
  const int columns = 1 + kTriadParameterCount + static_cast<int>(estimated.size());
  // Per pose: the contrast z_p = q_p . r_p and its derivative in the estimated parameters.
  Eigen::MatrixXd rows(pose_count, columns);
  std::vector<Eigen::Vector3d> normals(pose_count);
  for (int p = 0; p < pose_count; ++p) {
    TriadPoseContext context;
    context.time_s = poses[p].time_s - fit.time_origin_s;
    std::unique_ptr<ceres::CostFunction> cost(TriadPoseResidual::CreateWithEffects(
        poses[p].mean, {1.0, 1.0, 1.0}, gravity_mps2, context));
    const double* blocks[3] = {fit.parameters.data(), fit.effects.data(), fit.directions[p].data()};
    double residual[3];
    double parameters_jacobian[3 * kTriadParameterCount];
    double effects_jacobian[3 * kTriadEffectCoefficientCount];
    double direction_jacobian[9];
    double* jacobians[3] = {parameters_jacobian, effects_jacobian, direction_jacobian};
    if (!cost->Evaluate(blocks, residual, jacobians))
      return Status::Error(StringPrintf("pose %d's residual cannot be evaluated", p));
    const Eigen::Vector3d n(fit.directions[p][0], fit.directions[p][1], fit.directions[p][2]);
    Eigen::Vector3d t1 = n.unitOrthogonal();
    Eigen::Vector3d t2 = n.cross(t1);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> jn(direction_jacobian);
    Eigen::Vector3d q = (jn * t1).cross(jn * t2);
    if (!(q.norm() > 0.0)) return Status::Error(StringPrintf("pose %d's direction is singular", p));
    q.normalize();
    normals[p] = q;
    rows(p, 0) = q.dot(Eigen::Vector3d(residual[0], residual[1], residual[2]));
    for (int j = 0; j < kTriadParameterCount; ++j) {
      rows(p, 1 + j) = q[0] * parameters_jacobian[j] +
                       q[1] * parameters_jacobian[kTriadParameterCount + j] +
                       q[2] * parameters_jacobian[2 * kTriadParameterCount + j];
    }
    for (size_t e = 0; e < estimated.size(); ++e) {
      const int c = estimated[e];
      rows(p, 1 + kTriadParameterCount + e) =
          q[0] * effects_jacobian[c] + q[1] * effects_jacobian[kTriadEffectCoefficientCount + c] +
          q[2] * effects_jacobian[2 * kTriadEffectCoefficientCount + c];
    }
  }
  // The Kalman filter over the poses in time order: state (axis k, process i), each a
  // stationary Gauss-Markov process of variance process_variance[k].
  std::vector<int> order(pose_count);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return poses[a].time_s < poses[b].time_s; });
  const int processes = static_cast<int>(correlation.correlation_s.size());
  const int states = 3 * processes;
  Eigen::MatrixXd estimate = Eigen::MatrixXd::Zero(states, columns);
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(states, states);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < processes; ++i)
      covariance(k * processes + i, k * processes + i) = correlation.process_variance[k];
  Eigen::MatrixXd whitened(pose_count, columns);
  double previous_s = 0.0;
  for (int j = 0; j < pose_count; ++j) {
    const int p = order[j];
    const TriadPoseMean& pose = poses[p];
    if (j > 0) {
      const double dt = std::max(pose.time_s - previous_s, 0.0);
      for (int i = 0; i < processes; ++i) {
        const double phi = std::exp(-dt / correlation.correlation_s[i]);
        for (int k = 0; k < 3; ++k) {
          const int s = k * processes + i;
          estimate.row(s) *= phi;
          covariance.row(s) *= phi;
          covariance.col(s) *= phi;
          covariance(s, s) += correlation.process_variance[k] * (1.0 - phi * phi);
        }
      }
    }
    previous_s = pose.time_s;
    Eigen::RowVectorXd h(states);
    double noise = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double qk = normals[p][k];
      double own = IndependentVariance(correlation, pose, k) + added_variance[k];
      for (int i = 0; i < processes; ++i) {
        const double x = std::max(pose.duration_s, 0.0) / correlation.correlation_s[i];
        const double b = WindowFactor(x);
        h(k * processes + i) = qk * b;
        own += correlation.process_variance[k] * (WindowVariance(x) - b * b);
      }
      noise += qk * qk * own;
    }
    const Eigen::VectorXd ph = covariance * h.transpose();
    const double variance = h.dot(ph) + noise;
    if (!(variance > 0.0) || !std::isfinite(variance))
      return Status::Error("the pose means' covariance is not positive definite");
    const Eigen::RowVectorXd innovation = rows.row(p) - h * estimate;
    whitened.row(j) = innovation / std::sqrt(variance);
    const Eigen::VectorXd gain = ph / variance;
    estimate += gain * innovation;
    covariance -= gain * ph.transpose();
    covariance = 0.5 * (covariance + covariance.transpose()).eval();
  }
  // One Gauss-Newton step of the estimated parameters: the whitened contrasts' least squares.
  const Eigen::VectorXd z = whitened.col(0);
  const Eigen::MatrixXd x = whitened.rightCols(columns - 1);
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> solver(x);
  const Eigen::VectorXd step = solver.solve(-z);
  const Eigen::VectorXd left = z + x * step;
  *chi2 = left.squaredNorm();
  if (innovations != nullptr) innovations->assign(left.data(), left.data() + left.size());
  return Status::Ok();
}

double QuantisationBiasVariance(double noise_variance, double step) {
  if (!(step > 0.0)) return 0.0;
  const double ratio = std::max(noise_variance, 0.0) / (step * step);
  if (ratio == 0.0) return step * step / 12.0;
  // Terms fall as exp(-4 pi^2 j^2 ratio) / j^2: one or two for sigma >= q / 3, up to 1e5 (a
  // tail below 1e-5 of the sum) as sigma -> 0.
  double sum = 0.0;
  for (int j = 1; j <= 100000; ++j) {
    const double term = std::exp(-4.0 * M_PI * M_PI * j * j * ratio) / (double(j) * j);
    sum += term;
    if (term < 1e-17 * sum) break;
  }
  return step * step / (2.0 * M_PI * M_PI) * sum;
}

double UnroundedNoiseVariance(double rounded_variance, double step) {
  if (!(step > 0.0) || !(rounded_variance > 0.0)) return std::max(rounded_variance, 0.0);
  // s^2(sigma^2) = sigma^2 + q^2/12 - B rises from 0 at sigma = 0 and exceeds sigma^2, so the
  // root lies in [0, s^2].
  double low = 0.0;
  double high = rounded_variance;
  for (int i = 0; i < 60; ++i) {
    const double middle = 0.5 * (low + high);
    const double rounded = middle + step * step / 12.0 - QuantisationBiasVariance(middle, step);
    (rounded < rounded_variance ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

namespace {

// The quantisation term of the header for the poses of `log`.
void QuantisationOfPoseMeans(const TriadLog& log, const std::vector<TriadPoseMean>& poses,
                             TriadPoseNoise* noise) {
  if (poses.empty()) return;
  const std::array<double, 3> white = PooledWithinPoseVariance(poses);
  std::vector<double> counts;
  for (const TriadPoseMean& pose : poses) counts.push_back(pose.sample_count);
  const double median_count = UpperMedian(counts);
  noise->output_step = OutputSteps(log);
  for (int k = 0; k < 3; ++k) {
    const double step = noise->output_step[k];
    const double unrounded = UnroundedNoiseVariance(white[k], step);
    noise->unrounded_stddev[k] = std::sqrt(unrounded);
    noise->quantisation_variance[k] = QuantisationBiasVariance(unrounded, step);
    if (noise->quantisation_variance[k] >= 0.01 * white[k] / median_count)
      noise->quantisation_material = true;
  }
}

}  // namespace

Status ParseTriadNoiseChoice(const std::string& text, TriadNoiseChoice* choice) {
  if (text == "auto") {
    *choice = TriadNoiseChoice::kAuto;
  } else if (text == "white") {
    *choice = TriadNoiseChoice::kWhite;
  } else if (text == "allan") {
    *choice = TriadNoiseChoice::kAllan;
  } else {
    return Status::Error("'" + text + "' is not a noise model; use auto, white or allan");
  }
  return Status::Ok();
}

Status SelectTriadPoseNoise(const TriadLog& log, const std::vector<StaticInterval>& intervals,
                            const std::vector<TriadPoseMean>& poses, TriadNoiseChoice choice,
                            double alpha, TriadPoseNoise* noise, bool* use_allan) {
  const Status allan = TriadPoseNoiseFromLog(log, intervals, poses, noise);
  *use_allan = false;
  if (!allan.ok()) *noise = TriadPoseNoise();
  QuantisationOfPoseMeans(log, poses, noise);
  // Where rounding dominates (sigma below about q/2), the samples take two or three values and
  // their variance changes from pose to pose with where the mean falls on the grid: the white
  // test's chi-square degrees of freedom do not hold (it rejected white noise in 11 of 60
  // simulated sessions at sigma = 0.1 q, tests/triad_pose_noise_test.cc), so no Allan model is
  // offered unless asked for.
  if (allan.ok() && noise->quantisation_material && choice != TriadNoiseChoice::kAllan)
    noise->candidate = TriadNoiseCandidate();
  if (!allan.ok()) {
    return choice == TriadNoiseChoice::kAllan ? allan.WithContext("--noise=allan") : Status::Ok();
  }
  *use_allan = choice == TriadNoiseChoice::kAllan ||
               (choice == TriadNoiseChoice::kAuto && noise->candidate.white_p_value < alpha / 4.0);
  return Status::Ok();
}

}  // namespace accelcal
