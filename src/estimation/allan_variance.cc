#include "estimation/allan_variance.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "common/format.h"
#include "estimation/noise_floor_detector.h"

namespace accelcal {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The three coefficients' regressors at tau: sigma^2 = N^2 x0 + B^2 x1 + K^2 x2.
std::array<double, 3> Regressors(double tau_s) {
  return {1.0 / tau_s, BiasInstabilityFactor() * BiasInstabilityFactor(), tau_s / 3.0};
}

double Model(const std::array<double, 3>& coefficients, double tau_s) {
  const std::array<double, 3> x = Regressors(tau_s);
  double sum = 0.0;
  for (int j = 0; j < 3; ++j) sum += std::max(0.0, coefficients[j]) * x[j];
  return sum;
}

void SetInterval(double confidence, AllanPoint* point) {
  const double alpha = 1.0 - confidence;
  point->avar_low = point->edf * point->avar / ChiSquareQuantile(1.0 - alpha / 2.0, point->edf);
  point->avar_high = point->edf * point->avar / ChiSquareQuantile(alpha / 2.0, point->edf);
}

// The interval (a chi-square quantile by bisection, the costly part) only when asked.
void SetDof(AllanNoiseKind kind, const AllanCurve& curve, double confidence, bool interval,
            AllanPoint* point) {
  point->dominant = kind;
  point->edf = 0.0;
  for (long long n : curve.segment_samples) {
    if (4 * point->cluster_samples <= n)
      point->edf += AllanEquivalentDof(kind, n, point->cluster_samples);
  }
  if (interval) SetInterval(confidence, point);
}

// The inverse normal CDF at p, by bisection on erfc (only a handful of calls).
double NormalQuantile(double p) {
  double low = -40.0, high = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (low + high);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

// The term from its coefficient c = value^2 and c's sigma.
AllanTerm Term(double coefficient, double coefficient_stddev, double z) {
  AllanTerm term;
  term.fitted = true;
  term.squared_raw = coefficient;
  term.squared = std::max(0.0, coefficient);
  term.squared_stddev = coefficient_stddev;
  term.value = std::sqrt(term.squared);
  term.resolved = coefficient - z * coefficient_stddev > 0.0;
  term.stddev = term.value > 0.0 ? coefficient_stddev / (2.0 * term.value) : 0.0;
  term.low = std::sqrt(std::max(0.0, coefficient - z * coefficient_stddev));
  term.high = std::sqrt(std::max(0.0, coefficient + z * coefficient_stddev));
  return term;
}

}  // namespace

double BiasInstabilityFactor() { return std::sqrt(2.0 * std::log(2.0) / kPi); }

const char* AllanNoiseKindName(AllanNoiseKind kind) {
  switch (kind) {
    case AllanNoiseKind::kWhite:
      return "white";
    case AllanNoiseKind::kBiasInstability:
      return "bias_instability";
    case AllanNoiseKind::kRandomWalk:
      return "random_walk";
  }
  return "white";
}

double AllanEquivalentDof(AllanNoiseKind kind, long long n, long long m) {
  const double phase_points = static_cast<double>(n) + 1.0;  // N
  const double md = static_cast<double>(m);
  double edf = 1.0;
  switch (kind) {
    case AllanNoiseKind::kWhite:
      edf = (3.0 * (phase_points - 1.0) / (2.0 * md) - 2.0 * (phase_points - 2.0) / phase_points) *
            4.0 * md * md / (4.0 * md * md + 5.0);
      break;
    case AllanNoiseKind::kBiasInstability:
      edf = m == 1 ? 2.0 * (phase_points - 2.0) * (phase_points - 2.0) / (2.3 * phase_points - 4.9)
                   : 5.0 * phase_points * phase_points / (4.0 * md * (phase_points + 3.0 * md));
      break;
    case AllanNoiseKind::kRandomWalk: {
      const double a = phase_points - 1.0;
      const double b = phase_points - 3.0;
      edf = (phase_points - 2.0) / md * (a * a - 3.0 * md * a + 4.0 * md * md) / (b * b);
      break;
    }
  }
  return std::max(1.0, edf);
}

Status ComputeAllanVariance(const std::vector<std::vector<double>>& segments,
                            double sample_period_s, const AllanOptions& options,
                            AllanCurve* curve) {
  if (!(sample_period_s > 0.0) || !std::isfinite(sample_period_s))
    return Status::Error(
        StringPrintf("sample period %g s is not a positive number", sample_period_s));
  if (!(options.confidence > 0.0 && options.confidence < 1.0))
    return Status::Error(StringPrintf("confidence %g is not within (0, 1)", options.confidence));
  *curve = AllanCurve();
  curve->sample_period_s = sample_period_s;
  long long longest = 0;
  for (size_t s = 0; s < segments.size(); ++s) {
    for (size_t i = 0; i < segments[s].size(); ++i) {
      if (!std::isfinite(segments[s][i]))
        return Status::Error(StringPrintf("segment %zu, sample %zu is not finite", s + 1, i + 1));
    }
    curve->segment_samples.push_back(static_cast<long long>(segments[s].size()));
    longest = std::max(longest, curve->segment_samples.back());
  }
  if (longest < 4) {
    return Status::Error(
        "no static segment holds 4 samples, the fewest an Allan variance needs; give longer "
        "segments");
  }
  // Cumulative sums of the data less the segment's mean, in long double: the differences of
  // sums then lose no digits to a large offset (raw ADC counts near 32768).
  std::vector<std::vector<long double>> sums(segments.size());
  for (size_t s = 0; s < segments.size(); ++s) {
    const std::vector<double>& y = segments[s];
    long double mean = 0.0L;
    for (double v : y) mean += v;
    if (!y.empty()) mean /= static_cast<long double>(y.size());
    sums[s].assign(y.size() + 1, 0.0L);
    for (size_t i = 0; i < y.size(); ++i) sums[s][i + 1] = sums[s][i] + (y[i] - mean);
  }
  for (long long m = 1; 4 * m <= longest; m *= 2) {
    AllanPoint point;
    point.cluster_samples = m;
    point.tau_s = static_cast<double>(m) * sample_period_s;
    long double total = 0.0L;
    for (size_t s = 0; s < segments.size(); ++s) {
      const long long n = curve->segment_samples[s];
      if (4 * m > n) continue;
      const std::vector<long double>& S = sums[s];
      for (long long k = 0; k + 2 * m <= n; ++k) {
        const long double d = S[k + 2 * m] - 2.0L * S[k + m] + S[k];
        total += d * d;
      }
      point.difference_count += n - 2 * m + 1;
      point.independent_clusters += n / m;
    }
    point.avar = static_cast<double>(
        total / (2.0L * static_cast<long double>(m) * static_cast<long double>(m) *
                 static_cast<long double>(point.difference_count)));
    SetDof(AllanNoiseKind::kWhite, *curve, options.confidence, true, &point);
    curve->points.push_back(point);
  }
  return Status::Ok();
}

Status FitAllanNoise(const AllanOptions& options, AllanCurve* curve, AllanNoiseFit* fit) {
  const std::array<bool, 3> asked = {options.fit_white, options.fit_bias_instability,
                                     options.fit_random_walk};
  std::vector<int> columns;
  for (int j = 0; j < 3; ++j)
    if (asked[j]) columns.push_back(j);
  const int p = static_cast<int>(columns.size());
  const int count = static_cast<int>(curve->points.size());
  if (p == 0) return Status::Error("no noise term to fit; ask for at least one");
  if (count < p + 1) {
    return Status::Error(StringPrintf(
        "%d Allan variance points for %d noise terms; fitting needs one more point than terms: "
        "give a longer static segment or fit fewer terms",
        count, p));
  }
  // Start from white-noise weights on the measured values, then weigh by the model.
  std::array<double, 3> coefficients{};
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(p, p);
  for (int iteration = 0; iteration <= options.iterations; ++iteration) {
    Eigen::MatrixXd a(count, p);
    Eigen::VectorXd b(count);
    Eigen::VectorXd w(count);
    for (int i = 0; i < count; ++i) {
      const AllanPoint& point = curve->points[i];
      const std::array<double, 3> x = Regressors(point.tau_s);
      for (int c = 0; c < p; ++c) a(i, c) = x[columns[c]];
      b(i) = point.avar;
      double model = iteration == 0 ? point.avar : Model(coefficients, point.tau_s);
      if (!(model > 0.0)) model = point.avar > 0.0 ? point.avar : 1.0;
      w(i) = point.edf / (2.0 * model * model);
    }
    const Eigen::MatrixXd normal = a.transpose() * w.asDiagonal() * a;
    const Eigen::VectorXd rhs = a.transpose() * w.asDiagonal() * b;
    const Eigen::LDLT<Eigen::MatrixXd> solver(normal);
    if (solver.info() != Eigen::Success || !(normal.determinant() > 0.0)) {
      return Status::Error(
          "the Allan variance does not determine the noise terms (singular fit); fit fewer "
          "terms");
    }
    const Eigen::VectorXd solution = solver.solve(rhs);
    covariance = solver.solve(Eigen::MatrixXd::Identity(p, p));
    coefficients = {0.0, 0.0, 0.0};
    for (int c = 0; c < p; ++c) coefficients[columns[c]] = solution(c);
    fit->chi2 = (w.array() * (a * solution - b).array().square()).sum();
    // The degrees of freedom of each point follow the term that dominates it in the model.
    for (AllanPoint& point : curve->points) {
      const std::array<double, 3> x = Regressors(point.tau_s);
      int dominant = 0;
      for (int j = 1; j < 3; ++j) {
        if (std::max(0.0, coefficients[j]) * x[j] >
            std::max(0.0, coefficients[dominant]) * x[dominant])
          dominant = j;
      }
      SetDof(static_cast<AllanNoiseKind>(dominant), *curve, options.confidence,
             iteration == options.iterations, &point);
    }
  }
  fit->dof = count - p;
  fit->coefficients = coefficients;
  fit->covariance_method = "weighted least squares";
  fit->bootstrap_series = 0;
  fit->covariance = {};
  for (int r = 0; r < p; ++r)
    for (int c = 0; c < p; ++c) fit->covariance[columns[r]][columns[c]] = covariance(r, c);
  SetAllanTermsFromCovariance(options, fit);
  return Status::Ok();
}

void SetAllanTermsFromCovariance(const AllanOptions& options, AllanNoiseFit* fit) {
  const std::array<bool, 3> asked = {options.fit_white, options.fit_bias_instability,
                                     options.fit_random_walk};
  const double z = NormalQuantile(0.5 + options.confidence / 2.0);
  AllanTerm* terms[3] = {&fit->white, &fit->bias_instability, &fit->random_walk};
  // The regressors carry the factors 2 ln 2 / pi and 1/3, so each coefficient is its term's
  // square.
  for (int j = 0; j < 3; ++j) {
    *terms[j] =
        asked[j] ? Term(fit->coefficients[j], std::sqrt(fit->covariance[j][j]), z) : AllanTerm();
  }
}

double ModelAllanVariance(const AllanNoiseFit& fit, double tau_s) {
  return Model({fit.white.squared, fit.bias_instability.squared, fit.random_walk.squared}, tau_s);
}

double PoseMeanVariance(const AllanNoiseFit& fit, double duration_s) {
  return ModelAllanVariance(fit, duration_s);
}

}  // namespace accelcal
