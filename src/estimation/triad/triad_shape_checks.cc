#include "estimation/triad/triad_shape_checks.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>

#include "common/format.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/statistics/extra_chi_square.h"

namespace accelcal {
namespace {

const char kAxis[3] = {'x', 'y', 'z'};

// The monomials of a direction's components of one degree, with their names.
struct Monomial {
  std::array<int, 3> powers{};
  std::string name;
};
std::vector<Monomial> Monomials(int degree) {
  std::vector<Monomial> list;
  for (int a = degree; a >= 0; --a) {
    for (int b = degree - a; b >= 0; --b) {
      Monomial m;
      m.powers = {a, b, degree - a - b};
      for (int k = 0; k < 3; ++k) {
        if (m.powers[k] == 0) continue;
        if (!m.name.empty()) m.name += " ";
        m.name += std::string("n_") + kAxis[k];
        if (m.powers[k] > 1) m.name += "^" + std::to_string(m.powers[k]);
      }
      list.push_back(m);
    }
  }
  return list;
}
double Evaluate(const Monomial& m, const std::array<double, 3>& n) {
  double value = 1.0;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < m.powers[k]; ++i) value *= n[k];
  return value;
}

// What the checks share: the poses, the whitening, the model and residual, and the units.
class Shapes {
 public:
  Shapes(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
         const TriadContrasts& contrasts, const TriadContrastWhitener& whitener,
         const Eigen::MatrixXd& model, const Eigen::VectorXd& residual,
         const TriadShapeContext& context)
      : poses_(poses),
        fit_(fit),
        contrasts_(contrasts),
        whitener_(whitener),
        model_(model),
        span_(model),
        residual_(residual),
        context_(context) {
    dof_ = static_cast<int>(model.rows()) -
           static_cast<int>(Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(model).rank());
    first_s_ = last_s_ = poses.empty() ? 0.0 : poses.front().time_s;
    for (const TriadPoseMean& pose : poses) {
      first_s_ = std::min(first_s_, pose.time_s);
      last_s_ = std::max(last_s_, pose.time_s);
    }
  }
  int poses() const { return static_cast<int>(poses_.size()); }
  const std::array<double, 3>& direction(int p) const { return fit_.directions[p]; }
  const Eigen::Vector3d& normal(int p) const { return contrasts_.normals[p]; }
  // The pose's time on [-1, 1] over the session.
  double scaled_time(int p) const {
    const double half = 0.5 * (last_s_ - first_s_);
    return half > 0.0 ? (poses_[p].time_s - first_s_) / half - 1.0 : 0.0;
  }
  double time_s(int p) const { return poses_[p].time_s; }
  const std::vector<int>& time_order() const { return contrasts_.time_order; }
  const Eigen::MatrixXd& model() const { return model_; }
  const Eigen::VectorXd& residual() const { return residual_; }
  const TriadShapeContext& context() const { return context_; }
  double mps2(int axis, double value) const { return value * context_.gain_mps2_per_unit[axis]; }

  // Offsets on one axis, f(p) on axis k.
  Eigen::MatrixXd OnAxis(int axis, const std::function<double(int)>& f) const {
    Eigen::MatrixXd offsets = Eigen::MatrixXd::Zero(poses(), 3);
    for (int p = 0; p < poses(); ++p) offsets(p, axis) = f(p);
    return offsets;
  }
  Eigen::MatrixXd Raw(const std::vector<Eigen::MatrixXd>& offsets) const {
    return TriadOffsetColumns(offsets, contrasts_.normals);
  }
  Status Whiten(const Eigen::MatrixXd& raw, Eigen::MatrixXd* whitened) const {
    return whitener_.Whiten(raw, whitened);
  }

  // The chi-square whitened columns remove beside the model, and its tail at their rank
  // (rank 0 when they add nothing, or leave no degree of freedom).
  struct Score {
    double delta = 0.0;
    int rank = 0;
    double p_value = 1.0;
  };
  // Whitened columns less their part in the model's span.
  Eigen::MatrixXd Beside(const Eigen::MatrixXd& columns) const { return span_.Beside(columns); }
  // What the model and a family of `rank` columns removing `delta` leave per degree of freedom,
  // at least 1.
  double ScatterBeside(double delta, int rank) const {
    const int left = dof_ - rank;
    return left > 0 ? std::max(1.0, (residual_.squaredNorm() - delta) / left) : 1.0;
  }

  Score Test(const Eigen::MatrixXd& columns) const {
    Score score;
    score.delta = span_.ExtraChiSquare(columns, residual_, &score.rank);
    if (score.rank == 0 || dof_ - score.rank < 1) return Score();
    score.p_value = ChiSquareSurvival(score.delta, score.rank);
    return score;
  }

 private:
  const std::vector<TriadPoseMean>& poses_;
  const TriadMlResult& fit_;
  const TriadContrasts& contrasts_;
  const TriadContrastWhitener& whitener_;
  const Eigen::MatrixXd& model_;
  const ModelSpan span_;
  const Eigen::VectorXd& residual_;
  const TriadShapeContext& context_;
  int dof_ = 0;  // the contrasts' degrees of freedom beside the model
  double first_s_ = 0.0;
  double last_s_ = 0.0;
};

// The direction's nearest axis end, in words ("+x", "-z").
std::string NearestAxis(const std::array<double, 3>& n) {
  int best = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(n[k]) > std::abs(n[best])) best = k;
  return std::string(n[best] >= 0.0 ? "+" : "-") + kAxis[best];
}

// A check of a fixed family of columns.
Status FixedFamily(const Shapes& shapes, const std::string& name, int axis, ShapeClass shape_class,
                   const Eigen::MatrixXd& raw, TriadShapeCheck* out, Eigen::VectorXd* beta) {
  ACCELCAL_RETURN_IF_ERROR(shapes.Whiten(raw, &out->columns));
  const Shapes::Score score = shapes.Test(out->columns);
  ResidualCheck& check = out->check;
  check.name = name;
  check.axis = axis;
  check.shape_class = shape_class;
  check.statistic = score.delta;
  check.dof = score.rank;
  check.p_value = score.p_value;
  if (beta != nullptr)
    *beta = ProjectedCoefficients(shapes.model(), out->columns, shapes.residual());
  return Status::Ok();
}

// Orientation, one power: offsets on every axis in the direction's monomials of that degree.
Status OrientationCheck(const Shapes& shapes, int degree, TriadShapeCheck* out) {
  const std::vector<Monomial> monomials = Monomials(degree);
  const int per_axis = static_cast<int>(monomials.size());
  for (int k = 0; k < 3; ++k)
    for (int m = 0; m < per_axis; ++m)
      out->offsets.push_back(
          shapes.OnAxis(k, [&](int p) { return Evaluate(monomials[m], shapes.direction(p)); }));
  ACCELCAL_RETURN_IF_ERROR(FixedFamily(shapes, StringPrintf("orientation_power_%d", degree), -1,
                                       ShapeClass::kOrientation, shapes.Raw(out->offsets), out,
                                       nullptr));
  ResidualCheck& check = out->check;
  if (check.dof == 0) return Status::Ok();
  // Its best single term: which axis, which power.
  double best = -1.0;
  int best_axis = 0, best_monomial = 0;
  double best_size = 0.0;
  for (int k = 0; k < 3; ++k) {
    for (int m = 0; m < per_axis; ++m) {
      const Eigen::MatrixXd one = out->columns.col(k * per_axis + m);
      const double gain = shapes.Test(one).delta;
      if (gain > best) {
        best = gain;
        best_axis = k;
        best_monomial = m;
        best_size = ProjectedCoefficients(shapes.model(), one, shapes.residual())[0];
      }
    }
  }
  check.axis = best_axis;
  const Monomial& m = monomials[best_monomial];
  const char axis = kAxis[best_axis];
  check.description = StringPrintf(
      "the %c output depends on orientation beyond the model, most like an offset of %.3g %s "
      "(%.2g m/s^2) times %s on %c (the power-%d terms of every axis remove chi2 %.1f on %d dof, "
      "p = %.2g; that term alone %.1f)",
      axis, best_size, shapes.context().unit.c_str(), shapes.mps2(best_axis, best_size),
      m.name.c_str(), axis, degree, check.statistic, static_cast<int>(check.dof), check.p_value,
      best);
  const bool own_power = m.powers[best_axis] == degree;
  if (own_power && degree == 3) {
    check.advice = StringPrintf(
        "a cubic scale term of %c (its output grows as the cube of the force along it): add a "
        "cubic term to %c's calibration, or keep the forces on %c within its linear range",
        axis, axis, axis);
  } else if (own_power && degree == 2) {
    check.advice = StringPrintf(
        "a quadratic scale term of %c the candidate test did not name on its own: see the "
        "candidates' table for scale_nonlinearity_%c",
        axis, axis);
  } else {
    check.advice = StringPrintf(
        "the %c offset changes with the orientation of the other axes (a board that flexes in "
        "its mount, a thermal gradient that follows the orientation): log temperature and the "
        "orientation of %c, and check the mount",
        axis, axis);
  }
  return Status::Ok();
}

// Time: u, u^2, u^3 on every axis.
Status TimeCheck(const Shapes& shapes, TriadShapeCheck* out) {
  for (int k = 0; k < 3; ++k)
    for (int power = 1; power <= 3; ++power)
      out->offsets.push_back(
          shapes.OnAxis(k, [&](int p) { return std::pow(shapes.scaled_time(p), power); }));
  Eigen::VectorXd beta;
  ACCELCAL_RETURN_IF_ERROR(
      FixedFamily(shapes, "time", -1, ShapeClass::kTime, shapes.Raw(out->offsets), out, &beta));
  ResidualCheck& check = out->check;
  if (check.dof == 0) return Status::Ok();
  // Each axis's fitted curve over the session; the axis that moves most (in m/s^2) leads.
  const int kGrid = 200;
  std::array<double, 3> range{}, start{}, end{}, turn_u{};
  std::array<int, 3> turn{};  // +1 a peak inside the session, -1 a trough, 0 monotonic
  for (int k = 0; k < 3; ++k) {
    auto curve = [&](double u) {
      return beta[3 * k] * u + beta[3 * k + 1] * u * u + beta[3 * k + 2] * u * u * u;
    };
    double low = HUGE_VAL, high = -HUGE_VAL, low_u = -1.0, high_u = -1.0;
    for (int i = 0; i <= kGrid; ++i) {
      const double u = -1.0 + 2.0 * i / kGrid;
      const double value = curve(u);
      if (value < low) low = value, low_u = u;
      if (value > high) high = value, high_u = u;
    }
    start[k] = curve(-1.0);
    end[k] = curve(1.0);
    range[k] = high - low;
    // A turn: the extreme inside the session stands out from both ends by a quarter of the
    // range.
    if (std::min(high - start[k], high - end[k]) > 0.25 * range[k]) {
      turn[k] = 1;
      turn_u[k] = high_u;
    } else if (std::min(start[k] - low, end[k] - low) > 0.25 * range[k]) {
      turn[k] = -1;
      turn_u[k] = low_u;
    }
  }
  int lead = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(shapes.mps2(k, range[k])) > std::abs(shapes.mps2(lead, range[lead]))) lead = k;
  check.axis = lead;
  const double first_s = shapes.time_s(shapes.time_order().front());
  const double last_s = shapes.time_s(shapes.time_order().back());
  const std::string& unit = shapes.context().unit;
  const std::string test = StringPrintf("chi2 %.1f on %d dof, p = %.2g", check.statistic,
                                        static_cast<int>(check.dof), check.p_value);
  // The size stated with its sigma: a linear function w . beta of the coefficients (the turn's
  // height over the ends' mean, or the change from the first pose to the last), whose variance is
  // w' (X' X)^+ w for the family's whitened columns beside the model, times what the model and
  // the family leave per degree of freedom when that exceeds 1. Near the model's span (few
  // degrees of freedom, poses held in an order that follows their direction) it is large.
  const Eigen::MatrixXd beside = shapes.Beside(out->columns);
  const Eigen::MatrixXd information = beside.transpose() * beside;
  const Eigen::MatrixXd covariance =
      Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(information).pseudoInverse();
  const double scatter = shapes.ScatterBeside(check.statistic, static_cast<int>(check.dof));
  auto sigma = [&](const Eigen::VectorXd& w) {
    return std::sqrt(std::max(0.0, scatter * w.dot(covariance * w)));
  };
  Eigen::VectorXd w = Eigen::VectorXd::Zero(9);
  const char a = kAxis[lead];
  if (turn[lead] != 0) {
    const double u = turn_u[lead];
    w[3 * lead] = u;
    w[3 * lead + 1] = u * u - 1.0;
    w[3 * lead + 2] = u * u * u;
    const double height = w.dot(beta);
    const double at_s = first_s + 0.5 * (u + 1.0) * (last_s - first_s);
    check.description = StringPrintf(
        "the %c offset %s then %s over the session, by %.3g +- %.2g %s (%.2g m/s^2) at its turn "
        "(t = %.4g s) against the ends' mean (the offsets' ranges over the session (%.3g, %.3g, "
        "%.3g) %s; %s)",
        a, turn[lead] > 0 ? "rises" : "falls", turn[lead] > 0 ? "falls" : "rises", std::abs(height),
        sigma(w), unit.c_str(), shapes.mps2(lead, std::abs(height)), at_s, range[0], range[1],
        range[2], unit.c_str(), test.c_str());
    check.advice =
        "a warm-up and a cool-down (or a room whose temperature turned): log temperature, and "
        "hold the sensor at one temperature while it is calibrated";
  } else {
    w[3 * lead] = 2.0;
    w[3 * lead + 2] = 2.0;
    check.description = StringPrintf(
        "the %c offset changes over the session beyond the model, by %+.3g +- %.2g %s (%.2g "
        "m/s^2) from the first pose to the last, not at a constant rate (the offsets' ranges over "
        "the session (%.3g, %.3g, %.3g) %s; %s)",
        a, end[lead] - start[lead], sigma(w), unit.c_str(),
        shapes.mps2(lead, end[lead] - start[lead]), range[0], range[1], range[2], unit.c_str(),
        test.c_str());
    check.advice =
        "a warm-up (let the sensor reach its working temperature before logging, or log "
        "temperature beside it), or a bias that wanders more slowly than a pose can show: a "
        "second session tells a repeatable warm-up from a wander";
  }
  return Status::Ok();
}

// The smallest p-value over candidates, each a few raw columns, whitened in chunks (the
// whitening of many columns under the correlated model would otherwise hold poses x candidates
// numbers at once). `score` gives a candidate's p-value (1: none) from its whitened columns.
struct Best {
  int candidate = -1;
  Shapes::Score score;
  Eigen::MatrixXd columns;
};
Status MinimumOverCandidates(const Shapes& shapes, int candidates, int width,
                             const std::function<void(int, Eigen::MatrixXd*)>& fill,
                             const std::function<Shapes::Score(int, const Eigen::MatrixXd&)>& score,
                             Best* best) {
  const int kChunk = std::max(1, 240 / width);
  for (int begin = 0; begin < candidates; begin += kChunk) {
    const int end = std::min(candidates, begin + kChunk);
    Eigen::MatrixXd raw = Eigen::MatrixXd::Zero(shapes.poses(), (end - begin) * width);
    for (int c = begin; c < end; ++c) {
      Eigen::MatrixXd block = Eigen::MatrixXd::Zero(shapes.poses(), width);
      fill(c, &block);
      raw.middleCols((c - begin) * width, width) = block;
    }
    Eigen::MatrixXd whitened;
    ACCELCAL_RETURN_IF_ERROR(shapes.Whiten(raw, &whitened));
    for (int c = begin; c < end; ++c) {
      const Eigen::MatrixXd columns = whitened.middleCols((c - begin) * width, width);
      const Shapes::Score candidate = score(c, columns);
      if (candidate.rank > 0 && (best->candidate < 0 || candidate.p_value < best->score.p_value)) {
        best->candidate = c;
        best->score = candidate;
        best->columns = columns;
      }
    }
  }
  return Status::Ok();
}

// The check's figures from the best candidate, its p-value times the candidates (Bonferroni).
void FromBest(const Best& best, int candidates, TriadShapeCheck* out) {
  out->columns = best.columns;
  out->candidates = candidates;
  out->check.statistic = best.score.delta;
  out->check.dof = best.score.rank;
  out->check.p_value = std::min(1.0, candidates * best.score.p_value);
}

// A change between two consecutive poses in time: of the offsets (3 columns) or of every
// parameter of the fit (the model's raw columns after the change).
Status StepCheck(const Shapes& shapes, const Eigen::MatrixXd& raw_model, bool calibration,
                 TriadShapeCheck* out) {
  const std::vector<int>& order = shapes.time_order();
  const int side = calibration ? 4 : 2;  // poses at least on each side
  // The change points: after order[side - 1 + c]; at most kMostChanges of them, evenly spaced
  // (a log of thousands of poses: the maximum's cost stays linear, its factor bounded).
  constexpr int kMostChanges = 200;
  const int all_changes = std::max(0, shapes.poses() - 2 * side + 1);
  const int changes = std::min(all_changes, kMostChanges);
  auto change = [&](int i) {
    return changes <= 1 || changes == all_changes
               ? i
               : static_cast<int>(
                     std::lround(static_cast<double>(i) * (all_changes - 1) / (changes - 1)));
  };
  const int width = calibration ? static_cast<int>(raw_model.cols()) : 3;
  std::vector<int> place(shapes.poses());
  for (int j = 0; j < shapes.poses(); ++j) place[order[j]] = j;
  auto fill = [&](int c, Eigen::MatrixXd* block) {
    for (int p = 0; p < shapes.poses(); ++p) {
      if (place[p] < side + change(c)) continue;
      if (calibration) {
        block->row(p) = raw_model.row(p);
      } else {
        for (int k = 0; k < 3; ++k) (*block)(p, k) = shapes.normal(p)[k];
      }
    }
  };
  Best best;
  ACCELCAL_RETURN_IF_ERROR(MinimumOverCandidates(
      shapes, changes, width, fill, [&](int, const Eigen::MatrixXd& c) { return shapes.Test(c); },
      &best));
  ResidualCheck& check = out->check;
  check.name = calibration ? "calibration_step" : "offset_step";
  check.shape_class = ShapeClass::kTime;
  if (best.candidate < 0) return Status::Ok();
  FromBest(best, changes, out);
  const int at = change(best.candidate);
  const int before = order[side - 1 + at];
  const int after = order[side + at];
  if (!calibration) {
    for (int k = 0; k < 3; ++k)
      out->offsets.push_back(
          shapes.OnAxis(k, [&](int p) { return place[p] >= side + at ? 1.0 : 0.0; }));
  }
  const std::string test = StringPrintf(
      "chi2 %.1f on %d dof, p = %.2g, the smallest of %d change points times "
      "their number",
      check.statistic, static_cast<int>(check.dof), check.p_value, changes);
  if (calibration) {
    check.description = StringPrintf(
        "the calibration changes between pose %d (t = %.4g s) and pose %d (t = %.4g s): every "
        "parameter refitted after it (%s)",
        before, shapes.time_s(before), after, shapes.time_s(after), test.c_str());
  } else {
    const Eigen::VectorXd size =
        ProjectedCoefficients(shapes.model(), best.columns, shapes.residual());
    const std::string& unit = shapes.context().unit;
    check.description = StringPrintf(
        "the offsets change by (%.3g, %.3g, %.3g) %s = (%.2g, %.2g, %.2g) m/s^2 between pose %d "
        "(t = %.4g s) and pose %d (t = %.4g s) (%s)",
        size[0], size[1], size[2], unit.c_str(), shapes.mps2(0, size[0]), shapes.mps2(1, size[1]),
        shapes.mps2(2, size[2]), before, shapes.time_s(before), after, shapes.time_s(after),
        test.c_str());
  }
  check.advice =
      "did the sensor move in its mount, or was it knocked, between those poses? Fix it in "
      "place and log again, or calibrate the two parts of the session apart";
  return Status::Ok();
}

// One pose off the model by itself.
Status OnePoseCheck(const Shapes& shapes, TriadShapeCheck* out) {
  Best best;
  ACCELCAL_RETURN_IF_ERROR(MinimumOverCandidates(
      shapes, shapes.poses(), 1, [&](int c, Eigen::MatrixXd* block) { (*block)(c, 0) = 1.0; },
      [&](int, const Eigen::MatrixXd& c) { return shapes.Test(c); }, &best));
  ResidualCheck& check = out->check;
  check.name = "one_pose";
  check.shape_class = ShapeClass::kPoseOrder;
  if (best.candidate < 0) return Status::Ok();
  FromBest(best, shapes.poses(), out);
  const int p = best.candidate;
  Eigen::MatrixXd along = Eigen::MatrixXd::Zero(shapes.poses(), 3);
  along.row(p) = shapes.normal(p).transpose();
  out->offsets.push_back(along);
  const double size = ProjectedCoefficients(shapes.model(), best.columns, shapes.residual())[0];
  const std::array<double, 3>& n = shapes.direction(p);
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(n[k]) > std::abs(n[axis])) axis = k;
  check.axis = axis;
  check.description = StringPrintf(
      "pose %d (t = %.4g s, gravity near %s) sits %.3g %s (%.2g m/s^2) %s the model by itself "
      "(chi2 %.1f, p = %.2g, the smallest of %d poses times their number)",
      p, shapes.time_s(p), NearestAxis(n).c_str(), std::abs(size), shapes.context().unit.c_str(),
      std::abs(shapes.mps2(axis, size)), size > 0.0 ? "beyond" : "short of", check.statistic,
      check.p_value, shapes.poses());
  check.advice =
      "was the sensor moved or touched while that pose was held? Hold that orientation again, "
      "or leave the pose out";
  return Status::Ok();
}

// Poses near one end of an axis's range that fall short of the model (their outputs nearer the
// middle of the range than the model's): the top j poses along +-n_k (j >= 2: one pose alone is
// the one-pose check's) get an offset toward the middle that is linear in their n_k (a hinge
// whose knot is free: 2 columns), and it must grow toward the end of the range. The chi-square
// tail at 2 dof stays valid with that restriction (it only removes rejections).
Status FullScaleCheck(const Shapes& shapes, const std::vector<TriadPoseMean>& poses, int axis,
                      TriadShapeCheck* out, int* hinges) {
  ResidualCheck& check = out->check;
  check.name = StringPrintf("full_scale_%c", kAxis[axis]);
  check.axis = axis;
  check.shape_class = ShapeClass::kFullScale;
  // Which way the axis's output grows with its force: the poses' own means against n_k.
  double mean = 0.0;
  for (const TriadPoseMean& pose : poses) mean += pose.mean[axis];
  mean /= static_cast<double>(poses.size());
  double covariance = 0.0;
  for (int p = 0; p < shapes.poses(); ++p)
    covariance += (poses[p].mean[axis] - mean) * shapes.direction(p)[axis];
  const double grows = covariance >= 0.0 ? 1.0 : -1.0;
  constexpr int kMostPerSign = 12;
  struct Hinge {
    int sign = 1;
    double lowest = 0.0;  // s n_k of the j-th pose
    int poses = 0;
  };
  std::vector<Hinge> candidates;
  for (const int sign : {1, -1}) {
    std::vector<double> levels;
    for (int p = 0; p < shapes.poses(); ++p) {
      const double a = sign * shapes.direction(p)[axis];
      if (a > 0.5) levels.push_back(a);
    }
    std::sort(levels.rbegin(), levels.rend());
    const int count = std::min<int>(kMostPerSign, static_cast<int>(levels.size()));
    for (int j = 2; j <= count; ++j) {
      if (j < static_cast<int>(levels.size()) && levels[j] >= levels[j - 1]) continue;  // ties
      candidates.push_back({sign, levels[j - 1], j});
    }
  }
  *hinges = static_cast<int>(candidates.size());
  if (candidates.empty()) return Status::Ok();
  auto fill = [&](int c, Eigen::MatrixXd* block) {
    const Hinge& h = candidates[c];
    for (int p = 0; p < shapes.poses(); ++p) {
      const double a = h.sign * shapes.direction(p)[axis];
      if (a < h.lowest) continue;
      // Toward the middle of the range: against the way the output grows at this end.
      const double toward = shapes.normal(p)[axis] * (-h.sign * grows);
      (*block)(p, 0) = toward;
      (*block)(p, 1) = toward * (a - h.lowest);
    }
  };
  // The shortfall at the j-th pose and at the end of the range (s n_k = 1).
  auto shortfalls = [&](const Eigen::MatrixXd& columns, const Hinge& h) {
    const Eigen::VectorXd beta = ProjectedCoefficients(shapes.model(), columns, shapes.residual());
    return std::make_pair(beta[0], beta[0] + beta[1] * (1.0 - h.lowest));
  };
  auto score = [&](int c, const Eigen::MatrixXd& columns) {
    Shapes::Score score = shapes.Test(columns);
    if (score.rank == 0) return score;
    const auto [inner, end] = shortfalls(columns, candidates[c]);
    if (!(inner >= 0.0 && end > inner)) score.p_value = 1.0;
    return score;
  };
  Best best;
  ACCELCAL_RETURN_IF_ERROR(MinimumOverCandidates(shapes, *hinges, 2, fill, score, &best));
  if (best.candidate < 0 || best.score.p_value >= 1.0) return Status::Ok();
  FromBest(best, *hinges, out);
  const Hinge& h = candidates[best.candidate];
  for (int c = 0; c < 2; ++c) {
    out->offsets.push_back(shapes.OnAxis(axis, [&](int p) {
      const double a = h.sign * shapes.direction(p)[axis];
      if (a < h.lowest) return 0.0;
      return -h.sign * grows * (c == 0 ? 1.0 : a - h.lowest);
    }));
  }
  const double at_end = shortfalls(best.columns, h).second;
  const char a = kAxis[axis];
  check.description = StringPrintf(
      "the %d poses nearest %c1 g on %c (%sn_%c >= %.3f) fall short of the model, by up to %.3g "
      "%s (%.2g m/s^2) toward the end of its range (chi2 %.1f on 2 dof, p = %.2g, the smallest of "
      "%d thresholds times their number)",
      h.poses, h.sign > 0 ? '+' : '-', a, h.sign > 0 ? "" : "-", a, h.lowest, at_end,
      shapes.context().unit.c_str(), shapes.mps2(axis, at_end), check.statistic, check.p_value,
      *hinges);
  check.advice = TriadFullScaleAdvice(axis, shapes.mps2(axis, at_end));
  return Status::Ok();
}

}  // namespace

std::string TriadFullScaleAdvice(int axis, double shortfall_mps2) {
  const char a = kAxis[axis];
  // Clipping at a range that ends near 1 g takes half a percent of g or more off the poses beyond
  // it; less is the output compressing toward the end of the range it was driven to.
  if (std::abs(shortfall_mps2) >= 0.005 * 9.81) {
    return StringPrintf(
        "is %c clipping? Its range may end near 1 g: check its full-scale setting, or leave those "
        "poses out",
        a);
  }
  return StringPrintf(
      "%c's output compresses toward the end of the range these poses reach (a nonlinearity the "
      "model's terms do not follow, or an output near its full scale): check %c's full-scale "
      "setting, and whether a wider range is more linear",
      a, a);
}

Eigen::MatrixXd TriadOffsetColumns(const std::vector<Eigen::MatrixXd>& offsets,
                                   const std::vector<Eigen::Vector3d>& normals) {
  Eigen::MatrixXd raw(static_cast<Eigen::Index>(normals.size()),
                      static_cast<Eigen::Index>(offsets.size()));
  for (size_t c = 0; c < offsets.size(); ++c)
    for (size_t p = 0; p < normals.size(); ++p) raw(p, c) = offsets[c].row(p).dot(normals[p]);
  return raw;
}

Status TriadShapeChecks(const std::vector<TriadPoseMean>& poses, const TriadMlResult& fit,
                        const TriadContrasts& contrasts, const TriadContrastWhitener& whitener,
                        const Eigen::MatrixXd& model, const Eigen::VectorXd& residual,
                        const TriadShapeContext& context, std::vector<TriadShapeCheck>* checks) {
  checks->clear();
  const Shapes shapes(poses, fit, contrasts, whitener, model, residual, context);
  auto keep = [&](TriadShapeCheck check) {
    if (check.check.dof > 0) checks->push_back(std::move(check));
  };
  for (const int degree : {2, 3}) {
    TriadShapeCheck check;
    ACCELCAL_RETURN_IF_ERROR(OrientationCheck(shapes, degree, &check));
    keep(std::move(check));
  }
  {
    TriadShapeCheck check;
    ACCELCAL_RETURN_IF_ERROR(TimeCheck(shapes, &check));
    keep(std::move(check));
  }
  const Eigen::MatrixXd raw_model = contrasts.rows.rightCols(contrasts.rows.cols() - 1);
  for (const bool calibration : {false, true}) {
    TriadShapeCheck check;
    ACCELCAL_RETURN_IF_ERROR(StepCheck(shapes, raw_model, calibration, &check));
    keep(std::move(check));
  }
  {
    TriadShapeCheck check;
    ACCELCAL_RETURN_IF_ERROR(OnePoseCheck(shapes, &check));
    keep(std::move(check));
  }
  for (int k = 0; k < 3; ++k) {
    TriadShapeCheck check;
    int hinges = 0;
    ACCELCAL_RETURN_IF_ERROR(FullScaleCheck(shapes, poses, k, &check, &hinges));
    // In the family whenever it has hinges, also when none falls short (p = 1 then): which way
    // the residuals lean must not decide how many checks share alpha.
    if (hinges > 0) checks->push_back(std::move(check));
  }
  return Status::Ok();
}

}  // namespace accelcal
