#include "estimation/statistics/chi_square.h"

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

// The continued fraction of the regularized incomplete beta I_x(a, b), for x < (a+1)/(a+b+2).
double BetaContinuedFraction(double a, double b, double x) {
  constexpr double kTiny = std::numeric_limits<double>::min() / kEpsilon;
  double c = 1.0;
  double d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::abs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m < kMaxIterations; ++m) {
    const double m2 = 2.0 * m;
    double an = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
    d = 1.0 + an * d;
    if (std::abs(d) < kTiny) d = kTiny;
    c = 1.0 + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    h *= d * c;
    an = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
    d = 1.0 + an * d;
    if (std::abs(d) < kTiny) d = kTiny;
    c = 1.0 + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEpsilon) break;
  }
  return h;
}

}  // namespace

double RegularizedBeta(double a, double b, double x) {
  if (!(x > 0.0)) return 0.0;
  if (!(x < 1.0)) return 1.0;
  const double log_front =
      std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  if (x < (a + 1.0) / (a + b + 2.0))
    return std::exp(log_front) * BetaContinuedFraction(a, b, x) / a;
  return 1.0 - std::exp(log_front) * BetaContinuedFraction(b, a, 1.0 - x) / b;
}

double FSurvival(double f, double d1, double d2) {
  if (!(f > 0.0)) return 1.0;
  return std::clamp(RegularizedBeta(0.5 * d2, 0.5 * d1, d2 / (d2 + d1 * f)), 0.0, 1.0);
}

double StudentTCdf(double t, double dof) {
  const double tail = 0.5 * RegularizedBeta(0.5 * dof, 0.5, dof / (dof + t * t));
  return t > 0.0 ? 1.0 - tail : tail;
}

double StudentTQuantile(double p, double dof) {
  if (p == 0.5) return 0.0;
  if (p < 0.5) return -StudentTQuantile(1.0 - p, dof);
  double low = 0.0, high = 1.0;
  while (StudentTCdf(high, dof) < p) high *= 2.0;
  for (int i = 0; i < 200 && high - low > 1e-13 * high; ++i) {
    const double middle = 0.5 * (low + high);
    (StudentTCdf(middle, dof) < p ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

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

double ChiSquareQuantile(double p, double dof) {
  // The mean is dof and the spread sqrt(2 dof); expand the bracket until it holds p.
  double low = 0.0;
  double high = dof + 10.0 * std::sqrt(2.0 * dof) + 10.0;
  while (ChiSquareCdf(high, dof) < p) high *= 2.0;
  while (high - low > 1e-12 * high) {
    const double middle = 0.5 * (low + high);
    if (ChiSquareCdf(middle, dof) < p) {
      low = middle;
    } else {
      high = middle;
    }
  }
  return 0.5 * (low + high);
}

}  // namespace accelcal
