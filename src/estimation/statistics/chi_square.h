#ifndef ACCELCAL_ESTIMATION_STATISTICS_CHI_SQUARE_H_
#define ACCELCAL_ESTIMATION_STATISTICS_CHI_SQUARE_H_

// The chi-square distribution, through the regularized incomplete gamma function
// (series below a+1, Lentz's continued fraction above), accurate to ~1e-14 relative for
// the degrees of freedom of a tilt test (tens of thousands) as for small ones.

namespace accelcal {

// P(X <= x) for X ~ chi-square(dof).
double ChiSquareCdf(double x, double dof);

// P(X > x), computed directly (no 1 - CDF cancellation in the far tail).
double ChiSquareSurvival(double x, double dof);

// x with P(chi2_dof <= x) = p, 0 < p < 1 (bisection on ChiSquareCdf, to 1e-12 relative).
double ChiSquareQuantile(double p, double dof);

// 2 min(P(X <= x), P(X > x)), capped at 1: the p-value of a two-sided test of the
// stated noise level (too large and too small residuals are both evidence).
double ChiSquareTwoSidedPValue(double x, double dof);

// P(X > f) for X ~ F(d1, d2), through the regularized incomplete beta function
// I_{d2 / (d2 + d1 f)}(d2 / 2, d1 / 2) (continued fraction, Lentz): the p-value of a
// likelihood-ratio test whose noise level is estimated from the residuals (d2 of them).
double FSurvival(double f, double d1, double d2);

// The regularized incomplete beta function I_x(a, b), a, b > 0.
double RegularizedBeta(double a, double b, double x);

// Student's t on `dof` degrees of freedom (any positive real): its CDF through I_x, and its
// quantile by bisection (p in (0, 1)).
double StudentTCdf(double t, double dof);
double StudentTQuantile(double p, double dof);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_STATISTICS_CHI_SQUARE_H_
