#ifndef ACCELCAL_ESTIMATION_TRIAD_TRIAD_SESSIONS_H_
#define ACCELCAL_ESTIMATION_TRIAD_TRIAD_SESSIONS_H_

// Repeatability: several sessions of one device, each calibrated on its own
// (estimation/triad/triad_ml_calibration.h), combined per parameter (issue 21, item 3;
// docs/repeatability.md). A within-session sigma (ceres::Covariance of one session) says how
// well that session's data pin its parameters down; it says nothing of how much the device
// itself changes between sessions (power cycles, temperature, remounting). On the MIMU4444
// array the offsets move 2 to 40 times their within-session sigma from one session to the
// next.
//
// Random-effects model, per parameter i (one at a time; the index is dropped below):
//
//   theta_s = mu + delta_s + e_s,   delta_s ~ N(0, tau^2),   e_s ~ N(0, C_s),   s = 1..S,
//
// theta_s the session's estimate, C_s its within-session variance (the covariance's diagonal),
// mu the device's common value, tau^2 the between-session variance.
//
// Estimator (Paule-Mandel, generalised Q-profile): with weights w_s = 1 / (tau^2 + C_s),
//   mu(tau^2) = sum w_s theta_s / sum w_s,   Q(tau^2) = sum w_s (theta_s - mu(tau^2))^2,
// Q(tau^2) ~ chi2_{S-1} at the true tau^2 and decreases in tau^2. tau^2 solves Q = S - 1, and
// is 0 when Q(0) <= S - 1 (the sessions agree within their own sigma). The interval of tau at
// confidence 1 - alpha solves Q = chi2_{S-1}(1 - alpha/2) and Q = chi2_{S-1}(alpha/2)
// (each bound 0 when Q(0) is already below); with S = 2 or 3 it spans one to two orders of
// magnitude, and the report says so. Q(0) is Cochran's test of "no between-session term":
// p = P(chi2_{S-1} > Q(0)).
//
// Several devices of one sensor model can share tau^2 (pooled): Q sums over the devices, each
// with its own mu_d, on sum_d (S_d - 1) degrees of freedom.
//
// A NEW session of the device (not one of the S): its estimate about mu_hat has variance
//   stddev_new_session^2 = tau^2 + C_new + Var(mu_hat),   Var(mu_hat) = 1 / sum w_s,
// with C_new the sessions' mean within variance. With equal C_s and tau^2 > 0 this is
// s^2 (1 + 1/S), s^2 the sample variance of the theta_s, so
//   (theta_new - mu_hat) / stddev_new_session ~ Student t on S - 1 degrees of freedom
// (on the pooled degrees of freedom for a pooled tau^2): the 95% interval is
// mu_hat +- t_{dof}(0.975) stddev_new_session. When tau^2 is 0 the variance is that of a known
// within sigma and t is conservative. Monte Carlo coverage: tests/triad_sessions_test.cc and
// problems/triad_repeatability.cc.

#include <array>
#include <string>
#include <vector>

#include "common/status.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/triad/triad_ml_calibration.h"
#include "estimation/triad/triad_session_calibration.h"
#include "models/triad.h"

namespace accelcal {

// One session's estimate of one parameter and its within-session variance C_s.
struct SessionEstimate {
  double value = 0.0;
  double variance = 0.0;
};

// tau^2 shared by one or more devices (groups), with its interval.
struct BetweenSessionVariance {
  double variance = 0.0;    // tau^2, Paule-Mandel, >= 0
  double stddev = 0.0;      // tau
  double stddev_low = 0.0;  // Q-profile interval of tau at `confidence`
  double stddev_high = 0.0;
  double confidence = 0.95;
  double degrees_of_freedom = 0.0;  // sum over devices of (S_d - 1)
  double q_at_zero = 0.0;           // Cochran's Q(0)
  double homogeneity_p = 1.0;       // P(chi2_dof > Q(0)): small when sessions differ
};

// Per parameter, for one device: every figure of docs/repeatability.md.
struct RandomEffectsEstimate {
  int session_count = 0;
  double common = 0.0;         // mu_hat, weighted mean
  double common_stddev = 0.0;  // sqrt(Var(mu_hat))
  BetweenSessionVariance between;
  double within_stddev = 0.0;        // sqrt(mean_s C_s): one session's own sigma
  double new_session_stddev = 0.0;   // sqrt(tau^2 + mean C_s + Var(mu_hat)) about mu_hat
  double interval_multiplier = 0.0;  // t_{dof}((1 + confidence) / 2)
};

// tau^2 common to the groups; each group needs 2 or more sessions with positive finite
// variances and finite values (a Status otherwise). `confidence` in (0, 1).
Status EstimateBetweenSessionVariance(const std::vector<std::vector<SessionEstimate>>& groups,
                                      double confidence, BetweenSessionVariance* between);

// The device's common value and new-session sigma for a given (own or pooled) tau^2.
RandomEffectsEstimate CombineSessions(const std::vector<SessionEstimate>& sessions,
                                      const BetweenSessionVariance& between);

// tau^2 from the device's own sessions, then CombineSessions.
Status EstimateRandomEffects(const std::vector<SessionEstimate>& sessions, double confidence,
                             RandomEffectsEstimate* estimate);

// An array of D devices recorded together in the same S sessions: a session can move every
// device alike (temperature, supply), so the deviations share a common part gamma_s:
//   theta_d,s = mu_d + gamma_s + delta_d,s + e_d,s,  gamma ~ N(0, sigma_g^2), delta ~ N(0, tau^2).
// Then the devices do not give D (S - 1) independent looks at the between-session variance:
// the common part is seen S - 1 times only. Two-way analysis of variance of the deviations
// from each device's mean r_d,s = theta_d,s - mean_s theta_d,s: with c_s = mean_d r_d,s,
//   MS_session = D sum_s c_s^2 / (S - 1)                  E = D sigma_g^2 + sigma_r^2,
//   MS_device  = sum (r_d,s - c_s)^2 / ((D - 1)(S - 1))  E = sigma_r^2 = tau^2 + C,
// and the variance of a new session about a device's plain mean is (sigma_g^2 + sigma_r^2)
// (1 + 1/S), estimated by MS_session / D + (1 - 1/D) MS_device (floored at the mean within
// variance), on Satterthwaite's degrees of freedom
//   (a1 M1 + a2 M2)^2 / ((a1 M1)^2 / (S - 1) + (a2 M2)^2 / ((D - 1)(S - 1))).
struct ArraySessionVariance {
  double common_variance = 0.0;  // sigma_g^2 (>= 0)
  double device_variance = 0.0;  // tau^2 = sigma_r^2 - mean C (>= 0)
  double common_share = 0.0;     // the common part's share of the deviations' sum of squares
  double total_variance = 0.0;   // sigma_g^2 + sigma_r^2 as estimated, >= mean C
  double degrees_of_freedom = 0.0;
};

// values[d][s]: device d, session s (the same S >= 2 sessions for every device, D >= 2);
// variances alike.
Status EstimateArraySessionVariance(const std::vector<std::vector<SessionEstimate>>& devices,
                                    ArraySessionVariance* array);

// --- Which session drifts (issue 44, item 8) ---
//
// Each session against the others, leave one out: for session s and parameter p, the random
// effects of the S - 1 other sessions (their own tau^2) give the interval a new session should
// fall in, common_{-s} +- t_{S-2} x stddev_new_session_{-s}; the pivot
//   t_{s,p} = (theta_s - common_{-s}) / stddev_new_session_{-s}
// is Student t on S - 2 degrees of freedom when session s is drawn like the others (exactly so
// with equal within variances and tau^2 > 0; conservative otherwise), its two-sided p-value
// p_{s,p} = P(|t_{S-2}| > |t_{s,p}|).
//
// Rule: a session is named as drifting when some parameter has p_{s,p} < level / P, P the
// sensor's parameter count (Bonferroni): outside the others' new-session interval at confidence
// 1 - level / P. A session drawn like the others is then named with probability at most `level`
// (per sensor), whatever the correlation between its parameters. The parameters named are those
// below level / P. It needs S >= 3 (two others to estimate tau from); with S = 3 the others'
// tau rests on 1 degree of freedom and t_1 at 1 - 0.05 / 24 is 153: only a gross jump is named,
// and the report gives each session's largest deviation whatever it is.

struct SessionDeviation {
  int parameter = 0;
  double value = 0.0;          // theta_s
  double others_common = 0.0;  // common_{-s}
  double others_new_session_stddev = 0.0;
  double deviation = 0.0;  // t_{s,p}, in the others' new-session sigmas
  double p_value = 1.0;    // two-sided, Student t on S - 2
};

struct SessionDrift {
  int session = 0;                        // index into the sessions
  SessionDeviation largest;               // the smallest p-value (largest |t|)
  std::vector<SessionDeviation> outside;  // p < level / P, in parameter order
  bool drifting() const { return !outside.empty(); }
};

struct SessionDriftCheck {
  bool checked = false;  // false with fewer than 3 sessions (`not_checked` says why)
  std::string not_checked;
  double level = 0.05;
  int parameter_count = 0;
  double parameter_level = 0.0;        // level / P
  double degrees_of_freedom = 0.0;     // S - 2
  double multiplier = 0.0;             // t_{S-2}(1 - parameter_level / 2)
  std::vector<SessionDrift> sessions;  // one per session, in order
  std::vector<int> drifting;           // the sessions named
};

// by_parameter[p][s]: parameter p's estimate in session s (every parameter the same sessions).
// Fails only on input no check can use (a parameter's sessions not finite and positive).
Status CheckSessionDrift(const std::vector<std::vector<SessionEstimate>>& by_parameter,
                         double level, SessionDriftCheck* check);

// --- The triad's 9 parameters ---

// Each session is calibrated on its own by CalibrateTriadSession
// (estimation/triad/triad_session_calibration.h), as the single-session `calibrate_imu --mode=ml`
// does with the noise-floor detector.

// The session's estimates of parameter `index`.
std::vector<SessionEstimate> SessionEstimatesOf(const std::vector<TriadMlResult>& sessions,
                                                int index);

using TriadRandomEffects = std::array<RandomEffectsEstimate, kTriadParameterCount>;

// The sessions' estimates of every parameter, by_parameter[p][s] (CheckSessionDrift's order).
std::vector<std::vector<SessionEstimate>> TriadSessionEstimates(
    const std::vector<TriadMlResult>& sessions);

// Every parameter's random-effects estimate from the device's own sessions (2 or more).
Status CombineTriadSessions(const std::vector<TriadMlResult>& sessions, double confidence,
                            TriadRandomEffects* combined);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_TRIAD_TRIAD_SESSIONS_H_
