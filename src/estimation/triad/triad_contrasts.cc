#include "estimation/triad/triad_contrasts.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include "common/format.h"
#include "residuals/triad_pose_residual.h"

namespace accelcal {
namespace {

// The variance of a window's mean of a unit Gauss-Markov process with x = window / correlation
// time, and the factor b of its covariance with another window's (triad_pose_noise.h).
double WindowVariance(double x) {
  if (x < 1e-4) return 1.0 - x / 3.0;
  return 2.0 * (x - 1.0 + std::exp(-x)) / (x * x);
}
double WindowFactor(double x) {
  if (x < 1e-4) return 1.0 + x * x / 24.0;
  return std::sinh(0.5 * x) / (0.5 * x);
}

// The independent part of pose p's mean variance on axis k (triad_pose_noise.h): the white and
// random-walk terms; never below s^2 / N_p.
double IndependentVariance(const TriadPoseCorrelation& model, const TriadPoseMean& pose, int k) {
  const double t = std::max(pose.duration_s, 1e-9);
  const double n = model.white_density[k];
  const double r = model.random_walk[k];
  return std::max(n * n / t + r * r * t / 3.0,
                  model.sample_variance[k] / std::max(pose.sample_count, 1));
}

}  // namespace

Status TriadPoseContrasts(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                          double gravity_mps2, TriadContrasts* contrasts) {
  const int pose_count = static_cast<int>(poses.size());
  if (static_cast<int>(fit.directions.size()) != pose_count)
    return Status::Error("the fit is not of these poses");
  const std::vector<int>& estimated = fit.effects_estimated;
  const int columns = 1 + kTriadParameterCount + static_cast<int>(estimated.size());
  contrasts->rows.resize(pose_count, columns);
  contrasts->normals.assign(pose_count, Eigen::Vector3d::Zero());
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
    const Eigen::Vector3d t1 = n.unitOrthogonal();
    const Eigen::Vector3d t2 = n.cross(t1);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> jn(direction_jacobian);
    Eigen::Vector3d q = (jn * t1).cross(jn * t2);
    if (!(q.norm() > 0.0)) return Status::Error(StringPrintf("pose %d's direction is singular", p));
    q.normalize();
    // The sign that makes q_p point along the pose's direction, so that a positive contrast is
    // an output larger in magnitude than the model's.
    if (q.dot(n) < 0.0) q = -q;
    contrasts->normals[p] = q;
    contrasts->rows(p, 0) = q.dot(Eigen::Vector3d(residual[0], residual[1], residual[2]));
    for (int j = 0; j < kTriadParameterCount; ++j) {
      contrasts->rows(p, 1 + j) = q[0] * parameters_jacobian[j] +
                                  q[1] * parameters_jacobian[kTriadParameterCount + j] +
                                  q[2] * parameters_jacobian[2 * kTriadParameterCount + j];
    }
    for (size_t e = 0; e < estimated.size(); ++e) {
      const int c = estimated[e];
      contrasts->rows(p, 1 + kTriadParameterCount + e) =
          q[0] * effects_jacobian[c] + q[1] * effects_jacobian[kTriadEffectCoefficientCount + c] +
          q[2] * effects_jacobian[2 * kTriadEffectCoefficientCount + c];
    }
  }
  contrasts->time_order.resize(pose_count);
  std::iota(contrasts->time_order.begin(), contrasts->time_order.end(), 0);
  std::stable_sort(contrasts->time_order.begin(), contrasts->time_order.end(),
                   [&](int a, int b) { return poses[a].time_s < poses[b].time_s; });
  return Status::Ok();
}

TriadContrastWhitener::TriadContrastWhitener(const std::vector<TriadPoseMean>& poses,
                                             const TriadMlResult& fit,
                                             const TriadContrasts& contrasts,
                                             const TriadPoseCorrelation& correlation,
                                             const std::array<double, 3>& added_variance)
    : poses_(poses),
      fit_(fit),
      contrasts_(contrasts),
      correlation_(correlation),
      added_variance_(added_variance) {}

Status TriadContrastWhitener::Whiten(const Eigen::MatrixXd& columns,
                                     Eigen::MatrixXd* whitened) const {
  const int pose_count = static_cast<int>(poses_.size());
  const std::vector<Eigen::Vector3d>& normals = contrasts_.normals;
  whitened->resize(pose_count, columns.cols());
  if (correlation_.empty()) {
    for (int j = 0; j < pose_count; ++j) {
      const int p = contrasts_.time_order[j];
      double variance = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double s = fit_.mean_stddev[p][k];
        variance += normals[p][k] * normals[p][k] * s * s;
      }
      if (!(variance > 0.0) || !std::isfinite(variance))
        return Status::Error(StringPrintf("pose %d's contrast has no variance", p));
      whitened->row(j) = columns.row(p) / std::sqrt(variance);
    }
    return Status::Ok();
  }
  // The Kalman filter over the poses in time order: state (axis k, process i), each a
  // stationary Gauss-Markov process of variance process_variance[k].
  const int processes = static_cast<int>(correlation_.correlation_s.size());
  const int states = 3 * processes;
  Eigen::MatrixXd estimate = Eigen::MatrixXd::Zero(states, columns.cols());
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(states, states);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < processes; ++i)
      covariance(k * processes + i, k * processes + i) = correlation_.process_variance[k];
  double previous_s = 0.0;
  for (int j = 0; j < pose_count; ++j) {
    const int p = contrasts_.time_order[j];
    const TriadPoseMean& pose = poses_[p];
    if (j > 0) {
      const double dt = std::max(pose.time_s - previous_s, 0.0);
      for (int i = 0; i < processes; ++i) {
        const double phi = std::exp(-dt / correlation_.correlation_s[i]);
        for (int k = 0; k < 3; ++k) {
          const int s = k * processes + i;
          estimate.row(s) *= phi;
          covariance.row(s) *= phi;
          covariance.col(s) *= phi;
          covariance(s, s) += correlation_.process_variance[k] * (1.0 - phi * phi);
        }
      }
    }
    previous_s = pose.time_s;
    Eigen::RowVectorXd h(states);
    double noise = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double qk = normals[p][k];
      double own = IndependentVariance(correlation_, pose, k) + added_variance_[k];
      for (int i = 0; i < processes; ++i) {
        const double x = std::max(pose.duration_s, 0.0) / correlation_.correlation_s[i];
        const double b = WindowFactor(x);
        h(k * processes + i) = qk * b;
        own += correlation_.process_variance[k] * (WindowVariance(x) - b * b);
      }
      noise += qk * qk * own;
    }
    const Eigen::VectorXd ph = covariance * h.transpose();
    const double variance = h.dot(ph) + noise;
    if (!(variance > 0.0) || !std::isfinite(variance))
      return Status::Error("the pose means' covariance is not positive definite");
    const Eigen::RowVectorXd innovation = columns.row(p) - h * estimate;
    whitened->row(j) = innovation / std::sqrt(variance);
    const Eigen::VectorXd gain = ph / variance;
    estimate += gain * innovation;
    covariance -= gain * ph.transpose();
    covariance = 0.5 * (covariance + covariance.transpose()).eval();
  }
  return Status::Ok();
}

}  // namespace accelcal
