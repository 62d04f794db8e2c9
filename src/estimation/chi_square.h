#ifndef ACCELCAL_ESTIMATION_CHI_SQUARE_H_
#define ACCELCAL_ESTIMATION_CHI_SQUARE_H_

// The chi-square distribution, through the regularized incomplete gamma function
// (series below a+1, Lentz's continued fraction above), accurate to ~1e-14 relative for
// the degrees of freedom of a tilt test (tens of thousands) as for small ones.

namespace accelcal {

// P(X <= x) for X ~ chi-square(dof).
double ChiSquareCdf(double x, double dof);

// P(X > x), computed directly (no 1 - CDF cancellation in the far tail).
double ChiSquareSurvival(double x, double dof);

// 2 min(P(X <= x), P(X > x)), capped at 1: the p-value of a two-sided test of the
// stated noise level (too large and too small residuals are both evidence).
double ChiSquareTwoSidedPValue(double x, double dof);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_CHI_SQUARE_H_
