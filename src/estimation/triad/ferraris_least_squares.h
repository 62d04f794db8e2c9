#ifndef ACCELCAL_ESTIMATION_TRIAD_FERRARIS_LEAST_SQUARES_H_
#define ACCELCAL_ESTIMATION_TRIAD_FERRARIS_LEAST_SQUARES_H_

// The least-squares counterpart of imucal's Ferraris closed form on the same six holds, with
// sigma (issue 20, item 4; docs/imucal.md), in accelcal's triad parameters (models/triad.h).
//
// Data: the six holds' means ubar_p (counts), 18 numbers. Noise model: every sample is the
// truth plus white noise, independent between samples and axes, of one variance s_k^2 per axis,
// pooled over the holds, s_k^2 = sum_p (N_p - 1) s_p,k^2 / sum_p (N_p - 1); a mean of N_p
// samples then has variance s_k^2 / N_p, and the residuals are whitened by it.
//
// With the holds' gravity directions unknown (2 each), the model u_p = b + K^-1 T^-1 g n_p has
// 9 + 12 = 21 unknowns for 18 observations: not everything is determined. Geometrically the
// means lie on the ellipsoid b + K^-1 T^-1 (g sphere), 9 numbers, and each point on it fixes
// one; six holds leave a 3-dimensional family. So, three analyses:
//
//   Identifiability: the Jacobian of the 18 whitened residuals in the 21 unknowns (directions
//   in their tangent planes), columns normalised to unit length, at the holds' solution; its
//   rank, and each triad parameter's weight in the null space (the norm of its row of the
//   right singular vectors beyond the rank). A weight above 0.1 names a parameter the holds
//   do not determine.
//
//   (a) Known directions, Ferraris's assumption made explicit (residuals/ferraris_hold_residual.h):
//   the holds are +-g along the axes of one orthogonal frame, whose rotation Q from accelcal's
//   frame is unknown (3). 12 unknowns, 18 observations, 6 degrees of freedom: chi2 tests that
//   opposite holds are antiparallel and the three pairs share one centre (it cannot test that
//   the pairs are orthogonal: that is assumed). All nine triad parameters with sigma, from
//   ceres::Covariance.
//
//   (b) Unknown directions (residuals/triad_pose_residual.h, directions on SphereManifold<3>):
//   the three misalignment angles held at a given value (the closed form's), offsets and gains
//   solved: 6 + 12 = 18 unknowns for 18 observations, an exact fit with no redundancy and no
//   fit statistic. Sigma of offsets and gains given the angles. The same fit with the angles
//   held at 0 shows how much they depend on the angles assumed.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "common/ferraris_session.h"
#include "common/status.h"
#include "estimation/solver/ceres_solve.h"
#include "estimation/solver/solver_report.h"
#include "estimation/triad/ferraris_calibration.h"
#include "models/imucal_convention.h"
#include "models/triad.h"

namespace accelcal {

struct FerrarisLeastSquaresOptions {
  QuietSolveOptions solve;  // LM, dense QR, tolerances 1e-14 (estimation/solver/ceres_solve.h)
  // Singular values of the normalised Jacobian below this times the largest count as zero.
  // Six holds give no near-zero values: the 3 null directions are exact (18 rows, 21 columns)
  // and the smallest non-zero one is ~0.3 of the largest on imucal's session.
  double rank_tolerance = 1e-4;
  double null_space_weight_limit = 0.1;  // above it, a parameter is not determined
};

using FerrarisHoldVectors = std::array<std::array<double, 3>, kFerrarisHoldCount>;

struct FerrarisIdentifiability {
  int observations = 3 * kFerrarisHoldCount;
  int unknowns = kTriadParameterCount + 2 * kFerrarisHoldCount;
  int rank = 0;
  std::vector<double> singular_values;        // of the column-normalised Jacobian, descending
  TriadParameters null_space_weight{};        // per triad parameter, in [0, 1]
  std::vector<std::string> identifiable;      // triad parameter names, weight <= limit
  std::vector<std::string> not_identifiable;  // weight > limit
};

struct FerrarisKnownDirectionsFit {  // (a)
  TriadParameters parameters{};
  TriadParameters stddev{};
  std::array<std::array<double, kTriadParameterCount>, kTriadParameterCount> covariance{};
  Eigen::Matrix3d frame_rotation = Eigen::Matrix3d::Identity();  // Q: a (imucal) = Q a'
  std::array<double, 3> frame_correction_rad{};                  // w, Q = Q0 Exp(w)
  std::array<double, 3> frame_correction_stddev_rad{};
  FerrarisHoldVectors whitened_residuals{};
  double chi2 = 0.0;
  int degrees_of_freedom = 3 * kFerrarisHoldCount - kTriadParameterCount - 3;  // 6
  double p_value = 0.0;                                                        // P(chi2_6 > chi2)
  SolverReport solver;
};

struct FerrarisUnknownDirectionsFit {             // (b)
  std::array<double, 3> held_misalignment_rad{};  // yz, zy, zx
  TriadParameters parameters{};                   // the angles as held
  TriadParameters stddev{};                       // 0 for the held angles
  FerrarisHoldVectors directions{};               // unit gravity directions, accelcal's frame
  double chi2 = 0.0;                              // ~0: an exact fit
  TriadParameters parameters_at_zero_angles{};    // the same fit, angles held at 0
  SolverReport solver;
};

struct FerrarisLeastSquaresResult {
  std::array<double, 3> noise_variance{};  // pooled s_k^2, counts^2
  FerrarisIdentifiability identifiability;
  FerrarisKnownDirectionsFit known_directions;
  FerrarisUnknownDirectionsFit unknown_directions;
};

// Everything the ferraris mode reports: the closed form in imucal's convention and in
// accelcal's, and the least-squares fits.
struct FerrarisAnalysis {
  ImucalCalibration closed_form;
  double hold_orthogonality = 0.0;  // FerrarisHoldOrthogonality
  TriadParameters closed_form_triad{};
  Eigen::Matrix3d frame_rotation = Eigen::Matrix3d::Identity();  // Q of the closed form
  FerrarisLeastSquaresResult least_squares;
};

// The three analyses above, started from the closed form (`closed_form_triad`, its rotation
// `frame_rotation`). Fails when a hold has fewer than 2 samples or an axis no noise (nothing
// to weight by), when a solve does not converge, or when ceres::Covariance cannot invert.
Status FerrarisLeastSquares(const FerrarisSession& session, double gravity_mps2,
                            const TriadParameters& closed_form_triad,
                            const Eigen::Matrix3d& frame_rotation,
                            const FerrarisLeastSquaresOptions& options,
                            FerrarisLeastSquaresResult* result);

// FerrarisClosedForm, ImucalToTriad, then FerrarisLeastSquares.
Status AnalyzeFerraris(const FerrarisSession& session, const FerrarisOptions& options,
                       const FerrarisLeastSquaresOptions& least_squares_options,
                       FerrarisAnalysis* analysis);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_FERRARIS_LEAST_SQUARES_H_
