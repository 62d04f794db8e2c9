#include "estimation/tilt_table/residual_checks.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "common/format.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/statistics/diagnostics.h"
#include "estimation/statistics/extra_chi_square.h"
#include "estimation/statistics/noise_analysis.h"
#include "models/sensor_model.h"

namespace accelcal {
namespace {

const char* kAxisName[2] = {"x", "y"};

// P(sup |Z(t)| > x) over t in [trim, 1 - trim] for the standardised Brownian bridge
// Z(t) = B(t) / sqrt(t (1 - t)) (Miller and Siegmund 1982): the null distribution of the
// square root of the largest step chi-square over the change points.
double SupStepTail(double x, double trim) {
  if (!(x > 1.0)) return 1.0;
  const double phi = std::exp(-0.5 * x * x) / std::sqrt(2.0 * M_PI);
  const double span = std::log((1.0 - trim) * (1.0 - trim) / (trim * trim));
  return std::clamp(4.0 * phi / x + x * phi * (1.0 - 1.0 / (x * x)) * span, 0.0, 1.0);
}

// P(Z > z) for a standard normal Z.
double UpperNormalTail(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

// The sentence of a curved trend: the cubic a0 + a1 u + a2 u^2 + a3 u^3 fitted (least squares)
// to what the final model leaves of the axis over the test, outliers set aside, read as
// monotonic or turning. The check's own columns (u^2, u^3 beside the model) decide whether a
// trend is there; they cannot say which way it turns, since u^2 alone turns at u = 0 whatever
// the data, so the description reads the residuals' own cubic, straight line included.
std::string DescribeTrend(const std::vector<double>& residual, const AxisNoise& noise, int axis,
                          const ResidualCheck& check) {
  const int n = static_cast<int>(residual.size());
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::Vector4d moment = Eigen::Vector4d::Zero();
  for (int i = 0; i < n; ++i) {
    if (noise.IsOutlier(i)) continue;
    const double u = DriftCoordinate(i, n);
    const Eigen::Vector4d powers(1.0, u, u * u, u * u * u);
    normal += powers * powers.transpose();
    moment += powers * residual[i];
  }
  const Eigen::Vector4d a = normal.ldlt().solve(moment);
  const auto curve = [&](double u) { return a[0] + u * (a[1] + u * (a[2] + u * a[3])); };
  // Turning points inside the test: the roots of a1 + 2 a2 u + 3 a3 u^2 in (-0.5, 0.5) where
  // the slope changes sign.
  std::vector<double> turns;
  const double qa = 3.0 * a[3], qb = 2.0 * a[2], qc = a[1];
  std::vector<double> roots;
  if (std::abs(qa) > 1e-12 * (std::abs(qb) + std::abs(qc))) {
    const double discriminant = qb * qb - 4.0 * qa * qc;
    if (discriminant > 0.0) {
      roots = {(-qb - std::sqrt(discriminant)) / (2.0 * qa),
               (-qb + std::sqrt(discriminant)) / (2.0 * qa)};
    }
  } else if (qb != 0.0) {
    roots = {-qc / qb};
  }
  for (const double root : roots) {
    if (root > -0.5 && root < 0.5) turns.push_back(root);
  }
  std::sort(turns.begin(), turns.end());
  const double start = curve(-0.5), end = curve(0.5);
  const std::string figures = StringPrintf("(u^2, u^3 beside the model: delta chi2 %.1f, p = %.2g)",
                                           check.statistic, check.p_value);
  const char* name = kAxisName[axis];
  const auto percent = [](double u) { return 100.0 * (u + 0.5); };
  if (turns.empty()) {
    return StringPrintf(
        "%s: a monotonic curved trend over the test, %s by %.2g m/s^2 from start "
        "to end %s",
        name, end > start ? "rising" : "falling", std::abs(end - start), figures.c_str());
  }
  if (turns.size() == 1) {
    const double top = curve(turns[0]);
    const bool peak = top > start;
    return StringPrintf(
        "%s: a trend over the test that %s then %s, %s at %.0f%% of the test (sample %d): %s by "
        "%.2g m/s^2, then %s by %.2g m/s^2 %s",
        name, peak ? "rises" : "falls", peak ? "falls" : "rises", peak ? "highest" : "lowest",
        percent(turns[0]), static_cast<int>(std::lround((turns[0] + 0.5) * (n - 1))),
        peak ? "rising" : "falling", std::abs(top - start), peak ? "falling" : "rising",
        std::abs(top - end), figures.c_str());
  }
  return StringPrintf(
      "%s: a trend over the test that turns twice, at %.0f%% and %.0f%% of the test (%+.2g, then "
      "%+.2g, then %+.2g m/s^2 from one turn to the next) %s",
      name, percent(turns[0]), percent(turns[1]), curve(turns[0]) - start,
      curve(turns[1]) - curve(turns[0]), end - curve(turns[1]), figures.c_str());
}

// A shape column whitened and projected off the model's span (twice, for columns nearly in
// it): z = e.r / |e| of the whitened residual r on what is left, e, and the coefficient e.r /
// |e|^2. `usable` is false when almost nothing is left outside the span.
struct ProjectedColumn {
  bool usable = false;
  double z = 0.0;
  double coefficient = 0.0;
};
ProjectedColumn Project(const std::vector<double>& shape, int axis, const AxisNoise& noise,
                        const ModelSpan& span, const Eigen::VectorXd& residual) {
  const Eigen::VectorXd column =
      WhitenedShapeColumn(shape, axis, noise, static_cast<int>(residual.size()));
  const Eigen::VectorXd left = span.Beside(column);
  ProjectedColumn projected;
  const double norm2 = left.squaredNorm();
  projected.usable = norm2 > 1e-10 * std::max(1e-300, column.squaredNorm());
  if (!projected.usable) return projected;
  const double dot = left.dot(residual);
  projected.z = dot / std::sqrt(norm2);
  projected.coefficient = dot / norm2;
  return projected;
}

// The thresholds of the full-scale check on s f: the levels with a fraction q of the samples
// at or above them, for q from 0.5% to 20%, each level once. Clipping just below the largest
// force an axis sees cuts off a few percent of a sweep, or one or two held positions.
std::vector<double> FullScaleThresholds(std::vector<double> signed_force) {
  std::sort(signed_force.begin(), signed_force.end(), std::greater<double>());
  const int n = static_cast<int>(signed_force.size());
  std::vector<double> thresholds;
  for (const double fraction : {0.005, 0.01, 0.02, 0.03, 0.05, 0.075, 0.1, 0.15, 0.2}) {
    const int rank = static_cast<int>(fraction * n);
    if (rank >= n) continue;
    const double level = signed_force[rank];
    if (thresholds.empty() || level < thresholds.back()) thresholds.push_back(level);
  }
  return thresholds;
}

// Clipping near full scale on one axis and one side (sign +1: near the largest positive
// force), or nothing when no threshold's hinge leaves the model's span.
bool FullScaleCheck(const CalibrationTest& test, const std::vector<double>& force_along, int axis,
                    int sign, const AxisNoise& noise, const ModelSpan& span,
                    const Eigen::VectorXd& residual, const ResidualChecksOptions& options,
                    ResidualCheck* check) {
  const int n = test.size();
  std::vector<double> signed_force(n);
  for (int i = 0; i < n; ++i) signed_force[i] = sign * force_along[i];
  int usable = 0;
  double best_z = -std::numeric_limits<double>::infinity();
  double best_threshold = 0.0, best_coefficient = 0.0;
  std::vector<double> best_hinge;
  for (const double threshold : FullScaleThresholds(signed_force)) {
    std::vector<double> hinge(n);
    for (int i = 0; i < n; ++i) hinge[i] = -sign * std::max(0.0, signed_force[i] - threshold);
    const ProjectedColumn projected = Project(hinge, axis, noise, span, residual);
    if (!projected.usable) continue;
    ++usable;
    if (projected.z > best_z) {
      best_z = projected.z;
      best_threshold = threshold;
      best_coefficient = projected.coefficient;
      best_hinge = std::move(hinge);
    }
  }
  if (usable == 0) return false;
  int samples = 0;
  double top = best_threshold;
  for (int i = 0; i < n; ++i) {
    samples += signed_force[i] > best_threshold;
    top = std::max(top, signed_force[i]);
  }
  const char* name = kAxisName[axis];
  const char side = sign > 0 ? '+' : '-';
  check->name = StringPrintf("%s: full scale %c", name, side);
  check->axis = axis;
  check->statistic = best_z > 0.0 ? best_z * best_z : 0.0;
  check->dof = 1;
  check->p_value = std::min(1.0, usable * UpperNormalTail(best_z));
  check->shape = {best_hinge};
  check->shape_class = ShapeClass::kFullScale;
  const double level_g = sign * best_threshold / options.gravity_mps2;
  check->description = StringPrintf(
      "%s: %d samples near %c1 g on %s (the model's force along %s beyond %+.3g m/s^2 = %+.2f "
      "g) fall short of the model, by up to %.2g m/s^2 at %+.3g m/s^2 (one-sided z = %.1f at the "
      "best of %d levels, p = %.2g)",
      name, samples, side, name, name, sign * best_threshold, level_g,
      best_coefficient * (top - best_threshold), sign * top, best_z, usable, check->p_value);
  check->advice = StringPrintf(
      "is %s clipping? Its range may end near %+.2f g: check the full-scale setting (or choose "
      "a larger range) and repeat the test",
      name, level_g);
  return true;
}

// One held position off the model on its own: the largest chi-square(1) of a position's
// offset column over the positions, Bonferroni over them.
bool OnePositionCheck(const CalibrationTest& test, const std::vector<StaticPosition>& positions,
                      int axis, const AxisNoise& noise, const ModelSpan& span,
                      const Eigen::VectorXd& residual, ResidualCheck* check) {
  const int n = test.size();
  int usable = 0;
  double best = -1.0, best_offset = 0.0;
  int best_position = -1;
  for (size_t p = 0; p < positions.size(); ++p) {
    std::vector<double> offset(n, 0.0);
    std::fill(offset.begin() + positions[p].begin, offset.begin() + positions[p].end, 1.0);
    const ProjectedColumn projected = Project(offset, axis, noise, span, residual);
    if (!projected.usable) continue;
    ++usable;
    if (projected.z * projected.z > best) {
      best = projected.z * projected.z;
      best_offset = projected.coefficient;
      best_position = static_cast<int>(p);
    }
  }
  if (usable == 0) return false;
  const StaticPosition& held = positions[best_position];
  const char* name = kAxisName[axis];
  check->name = StringPrintf("%s: one position", name);
  check->axis = axis;
  check->statistic = best;
  check->dof = 1;
  check->p_value = std::min(1.0, usable * ChiSquareSurvival(best, 1.0));
  std::vector<double> offset(n, 0.0);
  std::fill(offset.begin() + held.begin, offset.begin() + held.end, 1.0);
  check->shape = {offset};
  check->shape_class = ShapeClass::kPoseOrder;
  check->description = StringPrintf(
      "%s: the position held at theta = %.4g rad (samples %d to %d, position %d of %zu) sits "
      "%.2g m/s^2 %s the model on its own (delta chi2 %.1f at the worst of %d positions, p = "
      "%.2g)",
      name, test.theta_rad[held.begin], held.begin, held.end - 1, best_position + 1,
      positions.size(), std::abs(best_offset), best_offset > 0.0 ? "above" : "below",
      check->statistic, usable, check->p_value);
  check->advice =
      "was the sensor moved or touched while that position was held, or did the table not "
      "settle there? Check the log of that position, and hold each position still";
  return true;
}

// What the user can do about correlation left in the residuals (no shape: the noise).
std::string CorrelationAdvice() {
  return "the noise is correlated in time beyond its noise model: a filter in the sensor "
         "(a bandwidth below the sample rate) or a slow wander; state the sensor's filter, or "
         "log at a rate the noise is white at";
}

// What the user can do about a k-theta harmonic the model cannot make.
std::string HarmonicAdvice(const char* axis, int k) {
  const std::string cause =
      k == 1 ? std::string("a 1-theta shape the model's scale and angle terms cannot make")
             : StringPrintf(
                   "a term of power %d in the forces, or an error in the reported angle "
                   "that repeats %d times a turn (an off-centre encoder gives 2 theta)",
                   k, k);
  return StringPrintf(
      "the %s output depends on the table angle beyond the model: %s; check the table's angle "
      "against a reference and that the sensor sits flat and tight in its mount, and log at more "
      "angles",
      axis, cause.c_str());
}

}  // namespace

FittedOutputs EvaluateFit(const CalibrationTest& test, const ModelParameters<double>& values,
                          double gravity_mps2) {
  FittedOutputs fitted;
  CalibrationResiduals(test, values, gravity_mps2, &fitted.residual[0], &fitted.residual[1]);
  const int n = test.size();
  fitted.force_along[0].resize(n);
  fitted.force_along[1].resize(n);
  for (int i = 0; i < n; ++i) {
    CalibrationForcesAlongAxes(test.theta_rad[i], gravity_mps2, values, &fitted.force_along[0][i],
                               &fitted.force_along[1][i]);
  }
  return fitted;
}

Eigen::VectorXd WhitenedShapeColumn(const std::vector<double>& shape, int axis,
                                    const AxisNoise& noise, int rows) {
  Eigen::VectorXd column = Eigen::VectorXd::Zero(rows);
  const std::vector<double> white = noise.Whiten(shape);
  for (size_t i = 0; i < white.size() && static_cast<int>(2 * i) + axis < rows; ++i) {
    column[2 * i + axis] = white[i];
  }
  return column;
}

std::vector<double> AxisWhiteResiduals(const Eigen::VectorXd& residual, int axis, int samples,
                                       int endpoint_rows, const AxisNoise& noise) {
  const int rows = static_cast<int>(residual.size());
  std::vector<double> white;
  for (int i = 0; i < samples && 2 * i + axis < rows - endpoint_rows; ++i) {
    if (!noise.IsOutlier(i)) white.push_back(residual[2 * i + axis]);
  }
  return white;
}

std::vector<ResidualCheck> CorrelationChecks(const std::vector<double>& white, int axis,
                                             int ljung_box_lags) {
  const int m = static_cast<int>(white.size());
  double mean = 0.0;
  for (double value : white) mean += value;
  mean /= m;
  double variance = 0.0;
  for (double value : white) variance += (value - mean) * (value - mean);
  variance /= m;
  double lag1 = 0.0;
  for (int j = 1; j < m; ++j) lag1 += (white[j] - mean) * (white[j - 1] - mean);
  lag1 = variance > 0.0 ? lag1 / (m * variance) : 0.0;
  ResidualCheck check;
  check.name = StringPrintf("%s: lag-1 correlation", kAxisName[axis]);
  check.axis = axis;
  check.statistic = lag1;
  check.dof = 1;
  check.p_value = TwoSidedNormalTail(std::sqrt(static_cast<double>(m)) * lag1);
  check.description = StringPrintf("%s: residuals correlated, lag-1 %.2f (p = %.2g)",
                                   kAxisName[axis], lag1, check.p_value);
  check.advice = CorrelationAdvice();
  const WhitenessTest whiteness = LjungBox(white, ljung_box_lags);
  ResidualCheck portmanteau;
  portmanteau.name = StringPrintf("%s: portmanteau", kAxisName[axis]);
  portmanteau.axis = axis;
  portmanteau.statistic = whiteness.q;
  portmanteau.dof = whiteness.lags;
  portmanteau.p_value = whiteness.p_value;
  portmanteau.description =
      StringPrintf("%s: residuals not white (Ljung-Box Q = %.1f over %d lags, p = %.2g)",
                   kAxisName[axis], whiteness.q, whiteness.lags, whiteness.p_value);
  portmanteau.advice = CorrelationAdvice();
  return {check, portmanteau};
}

std::vector<ResidualCheck> CheckResiduals(const CalibrationTest& test,
                                          const Eigen::MatrixXd& jacobian,
                                          const Eigen::VectorXd& residual,
                                          const FittedOutputs& fitted, int endpoint_rows,
                                          const AxisNoise noise[2],
                                          const ResidualChecksOptions& options) {
  std::vector<ResidualCheck> checks;
  const int n = test.size();
  const int rows = static_cast<int>(jacobian.rows());
  // What the model can make, factored once for every check; `q` an orthonormal basis of it.
  const ModelSpan span(jacobian);
  const Eigen::MatrixXd& q = span.basis();
  auto shape_check = [&](const std::string& name, int axis,
                         const std::vector<std::vector<double>>& shapes) {
    Eigen::MatrixXd extra(rows, shapes.size());
    for (size_t c = 0; c < shapes.size(); ++c)
      extra.col(c) = WhitenedShapeColumn(shapes[c], axis, noise[axis], rows);
    int rank = 0;
    ResidualCheck check;
    check.name = StringPrintf("%s: %s", kAxisName[axis], name.c_str());
    check.axis = axis;
    check.statistic = span.ExtraChiSquare(extra, residual, &rank);
    check.dof = rank;
    check.p_value = rank > 0 ? ChiSquareSurvival(check.statistic, rank) : 1.0;
    check.shape = shapes;
    return std::make_pair(check, extra);
  };
  const std::vector<double> turn_direction = TurnDirection(test.theta_rad);
  const bool turns_both_ways =
      std::find(turn_direction.begin(), turn_direction.end(), 1.0) != turn_direction.end() &&
      std::find(turn_direction.begin(), turn_direction.end(), -1.0) != turn_direction.end();
  const std::vector<StaticPosition> positions = StaticPositions(test.theta_rad);

  for (int axis = 0; axis < 2; ++axis) {
    // Harmonics of theta.
    for (int k = 1; k <= options.max_harmonic; ++k) {
      std::vector<double> cosine(n), sine(n);
      for (int i = 0; i < n; ++i) {
        cosine[i] = std::cos(k * test.theta_rad[i]);
        sine[i] = std::sin(k * test.theta_rad[i]);
      }
      auto [check, extra] = shape_check(StringPrintf("%d theta harmonic", k), axis, {cosine, sine});
      if (check.dof == 0) continue;  // all of it inside the model, or aliased
      const Eigen::VectorXd beta = ProjectedCoefficients(jacobian, extra, residual);
      const double amplitude = std::hypot(beta[0], beta[1]);
      check.description = StringPrintf(
          "%s: a %d-theta harmonic of %.2g m/s^2 left (delta chi2 %.1f, %d dof, p = %.2g)",
          kAxisName[axis], k, amplitude, check.statistic, static_cast<int>(check.dof),
          check.p_value);
      check.shape_class = ShapeClass::kOrientation;
      check.advice = HarmonicAdvice(kAxisName[axis], k);
      checks.push_back(std::move(check));
    }
    // A curved trend over the test.
    {
      std::vector<double> square(n), cube(n);
      for (int i = 0; i < n; ++i) {
        const double u = DriftCoordinate(i, n);
        square[i] = u * u;
        cube[i] = u * u * u;
      }
      auto [check, extra] = shape_check("curved trend", axis, {square, cube});
      if (check.dof > 0) {
        check.shape_class = ShapeClass::kTime;
        check.description = DescribeTrend(fitted.residual[axis], noise[axis], axis, check);
        check.advice =
            "log the temperature beside the outputs, and let the sensor warm up (and the room "
            "settle) before the test; a trend that rises then falls is often a warm-up, then a "
            "cool-down";
        checks.push_back(std::move(check));
      }
    }
    // A bias that depends on the way the table turns; none when it turns one way only (the
    // column is then constant over the test, which only the endpoint rows could tell from the
    // bias, and that is the endpoint check's business).
    if (turns_both_ways) {
      auto [check, extra] = shape_check("turn direction", axis, {turn_direction});
      if (check.dof > 0) {
        const double difference = 2.0 * ProjectedCoefficients(jacobian, extra, residual)[0];
        check.shape_class = ShapeClass::kTurnDirection;
        check.description = StringPrintf(
            "%s: while the table turns up (theta increasing) the output reads %.2g m/s^2 %s than "
            "while it turns down (delta chi2 %.1f, 1 dof, p = %.2g)",
            kAxisName[axis], std::abs(difference), difference > 0.0 ? "more" : "less",
            check.statistic, check.p_value);
        check.advice =
            "hysteresis in the sensor, play in its mount, or a lag between the reported angle and "
            "the output: tighten the mount, check that the angle and the output are sampled "
            "together, and hold each angle still before it is read";
        checks.push_back(std::move(check));
      }
    }
    // Clipping near either end of the axis's range.
    for (const int sign : {1, -1}) {
      ResidualCheck check;
      if (FullScaleCheck(test, fitted.force_along[axis], axis, sign, noise[axis], span, residual,
                         options, &check))
        checks.push_back(std::move(check));
    }
    // One held position off the model.
    if (!positions.empty()) {
      ResidualCheck check;
      if (OnePositionCheck(test, positions, axis, noise[axis], span, residual, &check))
        checks.push_back(std::move(check));
    }
    const std::vector<double> white =
        AxisWhiteResiduals(residual, axis, n, endpoint_rows, noise[axis]);
    if (white.size() < 16) continue;
    // A step: the largest chi-square a step column removes over the change points c in
    // [trim, n - trim], each projected off the model. With g_i = a_i - b_i (the whitening of
    // sample i), the whitened step at c is g_i for i > c and a_c at c, so every c's
    // projection comes from suffix sums in one pass.
    {
      const std::vector<AxisNoise::Whitening> weights = noise[axis].WhiteningOf(n);
      const int p = static_cast<int>(q.cols());
      Eigen::VectorXd qr_sum = q.transpose() * residual;  // Q^T r (about 0 at the optimum)
      Eigen::VectorXd suffix_q = Eigen::VectorXd::Zero(p);
      double suffix_r = 0.0, suffix_g2 = 0.0;
      const int trim = std::max(10, static_cast<int>(0.02 * n));
      double best = 0.0, best_size = 0.0;
      int at = -1;
      for (int c = n - 1; c >= 1; --c) {
        const int row = 2 * c + axis;
        const double g = weights[c].current - weights[c].previous;
        const double b = weights[c].previous;
        // The step at c: s = (suffix of g over i > c) + a_c at c = suffix(g, i >= c) + b_c e_c.
        suffix_q += g * q.row(row).transpose();
        suffix_r += g * residual[row];
        suffix_g2 += g * g;
        if (c < trim || c > n - trim) continue;
        const Eigen::VectorXd qs = suffix_q + b * q.row(row).transpose();
        const double sr = suffix_r + b * residual[row] - qs.dot(qr_sum);
        const double ss = suffix_g2 + 2.0 * g * b + b * b - qs.squaredNorm();
        if (!(ss > 1e-9 * (suffix_g2 + 1.0))) continue;
        const double t = sr * sr / ss;
        if (t > best) {
          best = t;
          best_size = sr / ss;
          at = c;
        }
      }
      ResidualCheck check;
      check.name = StringPrintf("%s: step", kAxisName[axis]);
      check.axis = axis;
      check.statistic = best;
      check.dof = 1;
      check.p_value = SupStepTail(std::sqrt(best), static_cast<double>(trim) / n);
      const int sample = at >= 0 ? at : n;
      std::vector<double> step(n, 0.0);
      for (int i = sample; i < n; ++i) step[i] = 1.0;
      check.description = StringPrintf(
          "%s: a step of %.2g m/s^2 at sample %d (theta = %.3g rad) (delta chi2 %.1f at the best "
          "of the change points, p = %.2g)",
          kAxisName[axis], best_size, sample, sample < n ? test.theta_rad[sample] : 0.0,
          check.statistic, check.p_value);
      check.shape = {step};
      check.shape_class = ShapeClass::kTime;
      check.advice = StringPrintf(
          "did the sensor move, or was it knocked, at that time? Check the log and the mount near "
          "sample %d",
          sample);
      checks.push_back(std::move(check));
    }
    for (ResidualCheck& check : CorrelationChecks(white, axis, options.ljung_box_lags))
      checks.push_back(std::move(check));
  }
  if (endpoint_rows == 2) {
    ResidualCheck check;
    check.name = "endpoint";
    check.statistic = residual.tail(2).squaredNorm();
    check.dof = 2;
    check.p_value = ChiSquareSurvival(check.statistic, 2.0);
    check.description = StringPrintf(
        "the run's endpoint is off the landmark it is tied to (chi2 %.1f, 2 dof, p = %.2g)",
        check.statistic, check.p_value);
    check.advice =
        "check which landmark the run ended at, and the run's initial position and velocity; a "
        "run effect outside the catalogue (a bias that changes during the run) also shows here";
    checks.push_back(std::move(check));
  }
  return checks;
}

}  // namespace accelcal
