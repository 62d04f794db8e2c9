#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_CONTRASTS_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_CONTRASTS_H_

// A triad fit seen as one number per pose. A static pose's mean has 3 residuals and its own
// gravity direction, 2 unknowns; what the direction cannot absorb is one contrast per pose,
// z_p = q_p . r_p, with q_p the unit normal to the direction's two columns of the pose's
// Jacobian (about the pose's direction itself: the contrast is the error of the calibrated
// output's magnitude). Eliminating the directions this way is exact for the linearised problem
// (generalised least squares with per-pose nuisance unknowns), so everything discovery asks of
// what the fit leaves can be asked of the contrasts: an offset delta_p (the log's unit, per
// axis) added to pose p's mean moves z_p by q_p . delta_p.
//
// The contrasts are whitened under the pose means' noise model: independent poses (each
// contrast's variance sum_k q_pk^2 sigma_pk^2, with the fit's sigma_pk), or the correlation
// across poses of TriadPoseCorrelation (triad_discovery.h, built by triad_pose_noise.h), by a
// Kalman filter over its Gauss-Markov bank in time order (linear in the poses). Columns are
// whitened with the same operator, so a shape's chi-square (estimation/statistics/
// extra_chi_square.h) keeps its meaning under either model.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/triad/triad_discovery.h"
#include "estimation/triad/triad_ml_calibration.h"

namespace accelcal {

struct TriadContrasts {
  // Row p (pose order): the contrast z_p in the log's unit, then its derivatives in the fit's
  // estimated parameters (the 9, then fit.effects_estimated in order).
  Eigen::MatrixXd rows;
  std::vector<Eigen::Vector3d> normals;  // q_p
  std::vector<int> time_order;           // the poses by mid-time (stable)
};

// Fails when a pose's residual cannot be evaluated or its direction is singular.
Status TriadPoseContrasts(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                          double gravity_mps2, TriadContrasts* contrasts);

// Whitens columns of contrasts (rows in pose order, e.g. TriadContrasts::rows, or a shape's
// q_p . delta_p) into rows in time order (TriadContrasts::time_order), independent N(0, 1) under
// the model. `correlation` empty: each pose's contrast divided by its own standard deviation
// from fit.mean_stddev; else the Kalman filter, with `added_variance` per axis and pose (the
// quantisation term) beside the correlation model's own independent part.
class TriadContrastWhitener {
 public:
  TriadContrastWhitener(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                        const TriadContrasts& contrasts, const TriadPoseCorrelation& correlation,
                        const std::array<double, 3>& added_variance);
  // Fails when the covariance the filter builds is not positive definite.
  Status Whiten(const Eigen::MatrixXd& columns, Eigen::MatrixXd* whitened) const;

 private:
  const std::vector<TriadPoseMean>& poses_;
  const TriadMlResult& fit_;
  const TriadContrasts& contrasts_;
  const TriadPoseCorrelation& correlation_;
  std::array<double, 3> added_variance_;
};

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_CONTRASTS_H_
