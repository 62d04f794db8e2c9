#include "estimation/chi_square.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace accelcal {
namespace {

constexpr int kMaxIterations = 1000000;
constexpr double kEpsilon = 1e-16;

// log of x^a e^-x / Gamma(a), the common prefactor of both expansions.
double LogPrefactor(double a, double x) { return a * std::log(x) - x - std::lgamma(a); }

// Lower regularized gamma P(a, x) by its series; converges fast for x < a + 1.
double LowerBySeries(double a, double x) {
  double term = 1.0 / a;
  double sum = term;
  for (int n = 1; n < kMaxIterations; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEpsilon) break;
  }
  return sum * std::exp(LogPrefactor(a, x));
}

// Upper regularized gamma Q(a, x) by its continued fraction; for x >= a + 1.
double UpperByContinuedFraction(double a, double x) {
  constexpr double kTiny = std::numeric_limits<double>::min() / kEpsilon;
  double b = x + 1.0 - a;
  double c = 1.0 / kTiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < kMaxIterations; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEpsilon) break;
  }
  return std::exp(LogPrefactor(a, x)) * h;
}

}  // namespace

double ChiSquareCdf(double x, double dof) {
  if (!(x > 0.0)) return 0.0;
  const double a = 0.5 * dof;
  const double half_x = 0.5 * x;
  if (half_x < a + 1.0) return std::min(1.0, LowerBySeries(a, half_x));
  return std::max(0.0, 1.0 - UpperByContinuedFraction(a, half_x));
}

double ChiSquareSurvival(double x, double dof) {
  if (!(x > 0.0)) return 1.0;
  const double a = 0.5 * dof;
  const double half_x = 0.5 * x;
  if (half_x < a + 1.0) return std::max(0.0, 1.0 - LowerBySeries(a, half_x));
  return std::min(1.0, UpperByContinuedFraction(a, half_x));
}

double ChiSquareTwoSidedPValue(double x, double dof) {
  return std::min(1.0, 2.0 * std::min(ChiSquareCdf(x, dof), ChiSquareSurvival(x, dof)));
}

}  // namespace accelcal
