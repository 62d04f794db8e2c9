#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_SHAPE_CHECKS_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_SHAPE_CHECKS_H_

// What a triad fit leaves, named by its shape (issue 33, item 1): each check is a family of
// offsets delta_p (the log's unit, per axis) added to the pose means, seen through the contrasts
// (triad_contrasts.h: pose p's contrast moves by q_p . delta_p), whitened under the noise model
// and projected off the fit's span; its chi-square is what the family would remove
// (estimation/statistics/extra_chi_square.h). With n_p the pose's gravity direction (unit, the
// sensor's frame) and u_p its time scaled to [-1, 1] over the session:
//
//   orientation, power 2 / 3   on each axis k, the monomials of n_p of that degree (18 and 30
//                              columns; the 9 parameters already make every function of n_p
//                              of degree 0 to 2 in the contrasts, so what is left is of degree 3
//                              and 4); described by its best single term, "an offset on x of
//                              c n_x^3": which axis, which power;
//   time, per axis             u, u^2, u^3 on axis k: an offset that changes over the session
//                              beyond the model (a linear drift is a catalogue effect), described
//                              as monotonic or as rising then falling, with the turn's time;
//   step                       the offsets of the three axes change between two consecutive
//                              poses in time (3 columns), the largest chi-square over the change
//                              points with at least 2 poses on each side, Bonferroni over them;
//   calibration step           every parameter of the fit changes there (the model's own
//                              columns after the change point), likewise;
//   one pose                   pose p's contrast alone, the largest over the poses, Bonferroni;
//   full scale, per axis, sign poses near one end of axis k's range fall short of the model:
//                              the hinge -s max(0, s n_pk - t) on axis k for thresholds t at the
//                              poses with s n_pk > 0.5 (at most 12 per axis and sign),
//                              one-sided, Bonferroni over every hinge.
//
// Each p-value is valid under "the model and its noise model are right" (the chi-square tails
// for the linearised problem, the maxima by Bonferroni), so Holm over them with the discovery's
// other checks holds the level.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "estimation/discovery/check.h"
#include "estimation/triad/triad_contrasts.h"
#include "estimation/triad/triad_ml_calibration.h"

namespace accelcal {

struct TriadShapeCheck {
  ResidualCheck check;      // statistic: the chi-square removed; dof: its rank
  Eigen::MatrixXd columns;  // the family's whitened columns (time order), to allow for it
  int candidates = 1;       // the maxima's candidates (change points, poses, thresholds)
  // Per column, the offsets one unit of it adds to the pose means (poses x 3, the log's unit),
  // so that it can be taken out of the means and the model refitted; empty when the family is
  // not one of offsets (the calibration step).
  std::vector<Eigen::MatrixXd> offsets;
};

// The full-scale check's advice for a shortfall of `shortfall_mps2` at the end of axis `axis`'s
// range: clipping when it is half a percent of g or more, else an output that compresses there.
std::string TriadFullScaleAdvice(int axis, double shortfall_mps2);

// The raw contrast columns of offsets (TriadShapeCheck::offsets) under contrasts' normals.
Eigen::MatrixXd TriadOffsetColumns(const std::vector<Eigen::MatrixXd>& offsets,
                                   const std::vector<Eigen::Vector3d>& normals);

struct TriadShapeContext {
  std::string unit = "count";
  std::array<double, 3> gain_mps2_per_unit{{1.0, 1.0, 1.0}};
};

// `model`: the whitened contrasts' design (time order), `residual`: their whitened residual at
// the model's minimum under the noise model.
Status TriadShapeChecks(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                        const TriadContrasts& contrasts, const TriadContrastWhitener& whitener,
                        const Eigen::MatrixXd& model, const Eigen::VectorXd& residual,
                        const TriadShapeContext& context, std::vector<TriadShapeCheck>* checks);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_SHAPE_CHECKS_H_
