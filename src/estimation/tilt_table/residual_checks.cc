#include "estimation/tilt_table/residual_checks.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

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

}  // namespace

Eigen::VectorXd WhitenedShapeColumn(const std::vector<double>& shape, int axis,
                                    const AxisNoise& noise, int rows) {
  Eigen::VectorXd column = Eigen::VectorXd::Zero(rows);
  const std::vector<double> white = noise.Whiten(shape);
  for (size_t i = 0; i < white.size() && static_cast<int>(2 * i) + axis < rows; ++i) {
    column[2 * i + axis] = white[i];
  }
  return column;
}

std::vector<ResidualCheck> CheckResiduals(const CalibrationTest& test,
                                          const Eigen::MatrixXd& jacobian,
                                          const Eigen::VectorXd& residual, int endpoint_rows,
                                          const AxisNoise noise[2],
                                          const ResidualChecksOptions& options) {
  std::vector<ResidualCheck> checks;
  const int n = test.size();
  const int rows = static_cast<int>(jacobian.rows());
  // An orthonormal basis of what the model can make.
  const Eigen::MatrixXd q =
      jacobian.cols() > 0
          ? Eigen::MatrixXd(Eigen::HouseholderQR<Eigen::MatrixXd>(jacobian).householderQ() *
                            Eigen::MatrixXd::Identity(rows, jacobian.cols()))
          : Eigen::MatrixXd(rows, 0);
  auto shape_check = [&](const std::string& name, int axis,
                         const std::vector<std::vector<double>>& shapes) {
    Eigen::MatrixXd extra(rows, shapes.size());
    for (size_t c = 0; c < shapes.size(); ++c)
      extra.col(c) = WhitenedShapeColumn(shapes[c], axis, noise[axis], rows);
    int rank = 0;
    ResidualCheck check;
    check.name = StringPrintf("%s: %s", kAxisName[axis], name.c_str());
    check.axis = axis;
    check.statistic = ExtraChiSquare(jacobian, extra, residual, &rank);
    check.dof = rank;
    check.p_value = rank > 0 ? ChiSquareSurvival(check.statistic, rank) : 1.0;
    check.shape = shapes;
    return std::make_pair(check, extra);
  };

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
        const Eigen::VectorXd beta = ProjectedCoefficients(jacobian, extra, residual);
        double largest = 0.0;
        for (int i = 0; i < n; ++i)
          largest = std::max(largest, std::abs(beta[0] * square[i] + beta[1] * cube[i]));
        check.description = StringPrintf(
            "%s: a curved trend over the test (u^2, u^3) of up to %.2g m/s^2 (delta chi2 %.1f, "
            "p = %.2g)",
            kAxisName[axis], largest, check.statistic, check.p_value);
        checks.push_back(std::move(check));
      }
    }
    // The whitened residuals of this axis, in sample order, outliers left out.
    std::vector<double> white;
    std::vector<int> sample_of;
    for (int i = 0; i < n && 2 * i + axis < rows - endpoint_rows; ++i) {
      if (noise[axis].IsOutlier(i)) continue;
      white.push_back(residual[2 * i + axis]);
      sample_of.push_back(i);
    }
    const int m = static_cast<int>(white.size());
    if (m < 16) continue;
    double mean = 0.0;
    for (double value : white) mean += value;
    mean /= m;
    double variance = 0.0;
    for (double value : white) variance += (value - mean) * (value - mean);
    variance /= m;
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
      checks.push_back(std::move(check));
    }
    // Correlation left.
    {
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
      checks.push_back(std::move(check));
      const WhitenessTest whiteness = LjungBox(white, options.ljung_box_lags);
      ResidualCheck portmanteau;
      portmanteau.name = StringPrintf("%s: portmanteau", kAxisName[axis]);
      portmanteau.axis = axis;
      portmanteau.statistic = whiteness.q;
      portmanteau.dof = whiteness.lags;
      portmanteau.p_value = whiteness.p_value;
      portmanteau.description =
          StringPrintf("%s: residuals not white (Ljung-Box Q = %.1f over %d lags, p = %.2g)",
                       kAxisName[axis], whiteness.q, whiteness.lags, whiteness.p_value);
      checks.push_back(std::move(portmanteau));
    }
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
    checks.push_back(std::move(check));
  }
  return checks;
}

}  // namespace accelcal
