#include "estimation/statistics/allan_variance.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <utility>

#include "common/format.h"
#include "estimation/statistics/chi_square.h"
#include "estimation/statistics/noise_analysis.h"

namespace accelcal {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The three coefficients' regressors at tau: sigma^2 = N^2 x0 + B^2 x1 + K^2 x2.
std::array<double, 3> Regressors(double tau_s) {
  static const double kFloor = BiasInstabilityFactor() * BiasInstabilityFactor();
  return {1.0 / tau_s, kFloor, tau_s / 3.0};
}

// The model at regressors x (negative coefficients count as 0).
double ModelAt(const std::array<double, 3>& coefficients, const std::array<double, 3>& x) {
  double sum = 0.0;
  for (int j = 0; j < 3; ++j) sum += std::max(0.0, coefficients[j]) * x[j];
  return sum;
}

double Model(const std::array<double, 3>& coefficients, double tau_s) {
  return ModelAt(coefficients, Regressors(tau_s));
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
  point->edf = AllanCurveDof(kind, curve, point->cluster_samples);
  if (interval) SetInterval(confidence, point);
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

double AllanCurveDof(AllanNoiseKind kind, const AllanCurve& curve, long long m) {
  double edf = 0.0;
  for (long long n : curve.segment_samples)
    if (AllanSegmentUsed(n, m)) edf += AllanEquivalentDof(kind, n, m);
  return edf;
}

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
  std::vector<long long> sizes;
  for (const std::vector<double>& segment : segments)
    sizes.push_back(static_cast<long long>(segment.size()));
  AllanVarianceAccumulator accumulator;
  ACCELCAL_RETURN_IF_ERROR(accumulator.Start(sample_period_s, options, sizes));
  for (const std::vector<double>& segment : segments)
    ACCELCAL_RETURN_IF_ERROR(accumulator.Add(segment));
  return accumulator.Finish(curve);
}

Status AllanVarianceAccumulator::Start(double sample_period_s, const AllanOptions& options,
                                       const std::vector<long long>& segment_samples) {
  if (!(sample_period_s > 0.0) || !std::isfinite(sample_period_s))
    return Status::Error(
        StringPrintf("sample period %g s is not a positive number", sample_period_s));
  if (!(options.confidence > 0.0 && options.confidence < 1.0))
    return Status::Error(StringPrintf("confidence %g is not within (0, 1)", options.confidence));
  const long long held_sums = held_sums_;
  *this = AllanVarianceAccumulator();
  held_sums_ = held_sums;
  options_ = options;
  curve_.sample_period_s = sample_period_s;
  curve_.segment_samples = segment_samples;
  for (long long n : segment_samples) longest_ = std::max(longest_, n);
  for (long long m = 1; 4 * m <= longest_; m *= 2) {
    AllanPoint point;
    point.cluster_samples = m;
    point.tau_s = static_cast<double>(m) * sample_period_s;
    curve_.points.push_back(point);
  }
  totals_.assign(curve_.points.size(), 0.0L);
  return Status::Ok();
}

Status AllanVarianceAccumulator::Add(const std::vector<double>& y) {
  const size_t s = added_++;
  for (size_t i = 0; i < y.size(); ++i) {
    if (!std::isfinite(y[i]))
      return Status::Error(StringPrintf("segment %zu, sample %zu is not finite", s + 1, i + 1));
  }
  // Cumulative sums of the data less the segment's mean, in long double: the differences of
  // sums then lose no digits to a large offset (raw ADC counts near 32768).
  long double mean = 0.0L;
  for (double v : y) mean += v;
  if (!y.empty()) mean /= static_cast<long double>(y.size());
  sums_.assign(y.size() + 1, 0.0L);
  for (size_t i = 0; i < y.size(); ++i) sums_[i + 1] = sums_[i] + (y[i] - mean);
  const long long n = static_cast<long long>(y.size());
  for (size_t p = 0; p < curve_.points.size(); ++p) {
    AllanPoint& point = curve_.points[p];
    const long long m = point.cluster_samples;
    if (!AllanSegmentUsed(n, m)) continue;
    const std::vector<long double>& S = sums_;
    for (long long k = 0; k + 2 * m <= n; ++k) {
      const long double d = S[k + 2 * m] - 2.0L * S[k + m] + S[k];
      totals_[p] += d * d;
    }
    point.difference_count += n - 2 * m + 1;
    point.independent_clusters += n / m;
  }
  sums_ = std::vector<long double>();
  return Status::Ok();
}

namespace {

// A segment's values read in order, in batches.
class SegmentCursor {
 public:
  SegmentCursor(const AllanVarianceAccumulator::SegmentReader& read, long long samples)
      : read_(read), samples_(samples) {}

  // The next value (at most `samples` of them).
  Status Next(double* value) {
    if (position_ == static_cast<long long>(batch_.size())) {
      const long long count = std::min(kBatch, samples_ - first_);
      batch_.resize(static_cast<size_t>(count));
      ACCELCAL_RETURN_IF_ERROR(read_(first_, count, batch_.data()));
      first_ += count;
      position_ = 0;
    }
    *value = batch_[static_cast<size_t>(position_++)];
    return Status::Ok();
  }

 private:
  static constexpr long long kBatch = 1 << 16;
  const AllanVarianceAccumulator::SegmentReader& read_;
  const long long samples_;
  long long first_ = 0;  // of the next batch
  std::vector<double> batch_;
  long long position_ = 0;  // in batch_
};

}  // namespace

Status AllanVarianceAccumulator::AddStreamed(long long n, const SegmentReader& read) {
  const size_t s = added_++;
  // The first pass: every value finite (the first that is not is named, as Add names it), and
  // the mean in Add's order.
  long double mean = 0.0L;
  {
    SegmentCursor cursor(read, n);
    for (long long i = 0; i < n; ++i) {
      double v = 0.0;
      ACCELCAL_RETURN_IF_ERROR(cursor.Next(&v));
      if (!std::isfinite(v))
        return Status::Error(StringPrintf("segment %zu, sample %lld is not finite", s + 1, i + 1));
      mean += v;
    }
  }
  if (n > 0) mean /= static_cast<long double>(n);
  // The points this segment enters, and where each one's lags m and 2m are read: the ring, or
  // the cursor of that lag.
  struct Lagged {
    size_t point = 0;
    long long m = 0;
    int cursor_m = -1;  // index into `lags`, -1: the ring
    int cursor_2m = -1;
  };
  std::vector<Lagged> used;
  std::vector<long long> lags;  // the lags read by cursors, each once
  auto cursor_of = [&](long long lag) {
    if (lag < held_sums_) return -1;
    for (size_t c = 0; c < lags.size(); ++c)
      if (lags[c] == lag) return static_cast<int>(c);
    lags.push_back(lag);
    return static_cast<int>(lags.size() - 1);
  };
  for (size_t p = 0; p < curve_.points.size(); ++p) {
    AllanPoint& point = curve_.points[p];
    const long long m = point.cluster_samples;
    if (!AllanSegmentUsed(n, m)) continue;
    used.push_back({p, m, cursor_of(m), cursor_of(2 * m)});
    point.difference_count += n - 2 * m + 1;
    point.independent_clusters += n / m;
  }
  // The second pass: S_i for i = 0 .. n (S_0 = 0), each point's difference ending at i once
  // i >= 2m, in Add's order (k = i - 2m increasing) and arithmetic.
  long long ring_size = 1;
  while (ring_size < std::min(n + 1, held_sums_)) ring_size *= 2;
  std::vector<long double> ring(static_cast<size_t>(ring_size), 0.0L);
  const long long mask = ring_size - 1;
  std::vector<SegmentCursor> behind;
  behind.reserve(lags.size());
  for (size_t c = 0; c < lags.size(); ++c) behind.emplace_back(read, n);
  std::vector<long double> behind_sum(lags.size(), 0.0L);  // S_{i - lag}
  SegmentCursor ahead(read, n);
  long double sum = 0.0L;  // S_i
  for (long long i = 1; i <= n; ++i) {
    double v = 0.0;
    ACCELCAL_RETURN_IF_ERROR(ahead.Next(&v));
    sum = sum + (v - mean);
    ring[static_cast<size_t>(i & mask)] = sum;
    for (size_t c = 0; c < lags.size(); ++c) {
      if (i <= lags[c]) continue;  // S_{i - lag} = S_0 = 0 at i == lag
      ACCELCAL_RETURN_IF_ERROR(behind[c].Next(&v));
      behind_sum[c] = behind_sum[c] + (v - mean);
    }
    for (const Lagged& lagged : used) {
      const long long m = lagged.m;
      if (i < 2 * m) break;  // the points are in increasing m
      const long double at_m = lagged.cursor_m < 0 ? ring[static_cast<size_t>((i - m) & mask)]
                                                   : behind_sum[lagged.cursor_m];
      const long double at_2m = lagged.cursor_2m < 0 ? ring[static_cast<size_t>((i - 2 * m) & mask)]
                                                     : behind_sum[lagged.cursor_2m];
      const long double d = sum - 2.0L * at_m + at_2m;
      totals_[lagged.point] += d * d;
    }
  }
  return Status::Ok();
}

Status AllanVarianceAccumulator::Finish(AllanCurve* curve) {
  if (longest_ < 4) {
    return Status::Error(
        "no static segment holds 4 samples, the fewest an Allan variance needs; give longer "
        "segments");
  }
  for (size_t p = 0; p < curve_.points.size(); ++p) {
    AllanPoint& point = curve_.points[p];
    const long double m = static_cast<long double>(point.cluster_samples);
    point.avar = static_cast<double>(
        totals_[p] / (2.0L * m * m * static_cast<long double>(point.difference_count)));
    SetDof(AllanNoiseKind::kWhite, curve_, options_.confidence, true, &point);
  }
  *curve = std::move(curve_);
  return Status::Ok();
}

namespace {

// The columns (terms) the options ask for.
std::vector<int> AskedColumns(const AllanOptions& options) {
  const std::array<bool, 3> asked = {options.fit_white, options.fit_bias_instability,
                                     options.fit_random_walk};
  std::vector<int> columns;
  for (int j = 0; j < 3; ++j)
    if (asked[j]) columns.push_back(j);
  return columns;
}

Status CheckFitSize(int terms, int points) {
  if (terms == 0) return Status::Error("no noise term to fit; ask for at least one");
  if (points < terms + 1) {
    return Status::Error(StringPrintf(
        "%d Allan variance points for %d noise terms; fitting needs one more point than terms: "
        "give a longer static segment",
        points, terms));
  }
  return Status::Ok();
}

// The term that dominates the model `coefficients` at tau.
AllanNoiseKind DominantKind(const std::array<double, 3>& coefficients, double tau_s) {
  const std::array<double, 3> x = Regressors(tau_s);
  int dominant = 0;
  for (int j = 1; j < 3; ++j) {
    if (std::max(0.0, coefficients[j]) * x[j] > std::max(0.0, coefficients[dominant]) * x[dominant])
      dominant = j;
  }
  return static_cast<AllanNoiseKind>(dominant);
}

// Solves the p x p system (p <= 3) `normal` x = rhs, the columns equilibrated first (the
// coefficients differ by orders of magnitude); false when singular.
bool SolveSmall(int p, std::array<std::array<double, 3>, 3> normal, std::array<double, 3> rhs,
                std::array<double, 3>* x) {
  std::array<double, 3> scale{};
  for (int r = 0; r < p; ++r) {
    if (!(normal[r][r] > 0.0) || !std::isfinite(normal[r][r])) return false;
    scale[r] = 1.0 / std::sqrt(normal[r][r]);
  }
  for (int r = 0; r < p; ++r) {
    rhs[r] *= scale[r];
    for (int c = 0; c < p; ++c) normal[r][c] *= scale[r] * scale[c];
  }
  // Gaussian elimination with partial pivoting on the equilibrated (unit-diagonal) matrix.
  std::array<int, 3> order = {0, 1, 2};
  for (int k = 0; k < p; ++k) {
    int pivot = k;
    for (int r = k + 1; r < p; ++r)
      if (std::fabs(normal[order[r]][k]) > std::fabs(normal[order[pivot]][k])) pivot = r;
    std::swap(order[k], order[pivot]);
    const double diagonal = normal[order[k]][k];
    if (!(std::fabs(diagonal) > 1e-12)) return false;
    for (int r = k + 1; r < p; ++r) {
      const double factor = normal[order[r]][k] / diagonal;
      for (int c = k; c < p; ++c) normal[order[r]][c] -= factor * normal[order[k]][c];
      rhs[order[r]] -= factor * rhs[order[k]];
    }
  }
  for (int k = p - 1; k >= 0; --k) {
    double sum = rhs[order[k]];
    for (int c = k + 1; c < p; ++c) sum -= normal[order[k]][c] * (*x)[c];
    (*x)[k] = sum / normal[order[k]][k];
  }
  for (int k = 0; k < p; ++k) (*x)[k] *= scale[k];
  return true;
}

// Weight 1 / var(sigma^2_hat) = edf / (2 model^2), model falling back on the measured value.
double Weight(double edf, double model, double measured) {
  if (!(model > 0.0)) model = measured > 0.0 ? measured : 1.0;
  return edf / (2.0 * model * model);
}

const char kSingularFit[] =
    "the Allan variance does not determine the noise terms (singular fit): its points cannot "
    "separate them (an output whose noise is below its quantisation step, or segments too short, "
    "give such a "
    "curve)";

}  // namespace

AllanFitter::AllanFitter(const AllanOptions& options, const AllanCurve& curve)
    : columns_(AskedColumns(options)), iterations_(options.iterations) {
  for (const AllanPoint& point : curve.points) {
    tau_s_.push_back(point.tau_s);
    x_.push_back(Regressors(point.tau_s));
    std::array<double, 3> edf;
    for (int kind = 0; kind < 3; ++kind)
      edf[kind] = AllanCurveDof(static_cast<AllanNoiseKind>(kind), curve, point.cluster_samples);
    edf_.push_back(edf);
  }
}

Status AllanFitter::Check() const {
  if (points() > kMaxFitPoints) {
    return Status::Error(StringPrintf("%d Allan variance points; the fit takes at most %d",
                                      points(), kMaxFitPoints));
  }
  return CheckFitSize(static_cast<int>(columns_.size()), points());
}

bool AllanFitter::Fit(const double* avar, std::array<double, 3>* coefficients, int term,
                      double fixed, std::vector<double>* weights) const {
  std::array<int, 3> free{};
  int p = 0;
  for (int column : columns_)
    if (column != term) free[p++] = column;
  *coefficients = {0.0, 0.0, 0.0};
  if (term >= 0) (*coefficients)[term] = fixed;
  // The weights of the previous pass: when they repeat, so would the solution.
  std::array<double, kMaxFitPoints> previous{};
  std::array<double, kMaxFitPoints> current{};
  for (int iteration = 0; iteration <= iterations_; ++iteration) {
    bool repeated = iteration > 0;
    for (int i = 0; i < points(); ++i) {
      const bool first = iteration == 0;
      const int kind = first ? 0 : static_cast<int>(DominantKind(*coefficients, tau_s_[i]));
      current[i] = Weight(edf_[i][kind], first ? avar[i] : ModelAt(*coefficients, x_[i]), avar[i]);
      repeated = repeated && std::fabs(current[i] - previous[i]) <= 1e-9 * previous[i];
    }
    if (repeated) break;
    std::array<std::array<double, 3>, 3> normal{};
    std::array<double, 3> rhs{};
    for (int i = 0; i < points(); ++i) {
      const std::array<double, 3>& x = x_[i];
      const double target = avar[i] - (term >= 0 ? fixed * x[term] : 0.0);
      for (int r = 0; r < p; ++r) {
        rhs[r] += current[i] * x[free[r]] * target;
        for (int c = 0; c < p; ++c) normal[r][c] += current[i] * x[free[r]] * x[free[c]];
      }
    }
    std::array<double, 3> solution{};
    if (p > 0 && !SolveSmall(p, normal, rhs, &solution)) return false;
    for (int r = 0; r < p; ++r) (*coefficients)[free[r]] = solution[r];
    previous = current;
  }
  if (weights != nullptr) weights->assign(current.begin(), current.begin() + points());
  return true;
}

double AllanFitter::Chi2(const double* avar, const std::array<double, 3>& coefficients,
                         const std::vector<double>& weights) const {
  double chi2 = 0.0;
  for (int i = 0; i < points(); ++i) {
    double fitted = 0.0;
    for (int j = 0; j < 3; ++j) fitted += coefficients[j] * x_[i][j];
    chi2 += weights[i] * (fitted - avar[i]) * (fitted - avar[i]);
  }
  return chi2;
}

Status FitAllanNoise(const AllanOptions& options, AllanCurve* curve, AllanNoiseFit* fit) {
  const AllanFitter fitter(options, *curve);
  ACCELCAL_RETURN_IF_ERROR(fitter.Check());
  const int count = fitter.points();
  std::vector<double> avar(count), weights;
  for (int i = 0; i < count; ++i) avar[i] = curve->points[i].avar;
  std::array<double, 3> coefficients;
  if (!fitter.Fit(avar.data(), &coefficients, -1, 0.0, &weights))
    return Status::Error(kSingularFit);
  // The fit's chi2 and least squares covariance (A^T W A)^-1 at the final weights.
  const std::vector<int> columns = AskedColumns(options);
  const int p = static_cast<int>(columns.size());
  fit->chi2 = fitter.Chi2(avar.data(), coefficients, weights);
  fit->chi2_bootstrap_fraction = -1.0;
  Eigen::MatrixXd a(count, p);
  for (int i = 0; i < count; ++i) {
    const std::array<double, 3> x = Regressors(curve->points[i].tau_s);
    for (int c = 0; c < p; ++c) a(i, c) = x[columns[c]];
  }
  const Eigen::MatrixXd normal =
      a.transpose() * Eigen::Map<const Eigen::VectorXd>(weights.data(), count).asDiagonal() * a;
  const Eigen::LDLT<Eigen::MatrixXd> solver(normal);
  if (solver.info() != Eigen::Success || !(normal.determinant() > 0.0))
    return Status::Error(kSingularFit);
  const Eigen::MatrixXd covariance = solver.solve(Eigen::MatrixXd::Identity(p, p));
  // The degrees of freedom and interval of each point follow the term that dominates it in the
  // model.
  for (AllanPoint& point : curve->points)
    SetDof(DominantKind(coefficients, point.tau_s), *curve, options.confidence, true, &point);
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
  const double z = TwoSidedNormalQuantile(1.0 - options.confidence);
  AllanTerm* terms[3] = {&fit->white, &fit->bias_instability, &fit->random_walk};
  // The regressors carry the factors 2 ln 2 / pi and 1/3, so each coefficient is its term's
  // square.
  for (int j = 0; j < 3; ++j) {
    *terms[j] =
        asked[j] ? Term(fit->coefficients[j], std::sqrt(fit->covariance[j][j]), z) : AllanTerm();
  }
}

AllanNoiseTerms FittedNoiseTerms(const AllanNoiseFit& fit) {
  AllanNoiseTerms terms;
  terms.white_density = fit.white.value;
  terms.bias_instability = fit.bias_instability.value;
  terms.random_walk = fit.random_walk.value;
  return terms;
}

double ModelAllanVariance(const AllanNoiseTerms& terms, double tau_s) {
  return Model(
      {terms.white_density * terms.white_density, terms.bias_instability * terms.bias_instability,
       terms.random_walk * terms.random_walk},
      tau_s);
}

double ModelAllanVariance(const AllanNoiseFit& fit, double tau_s) {
  return ModelAllanVariance(FittedNoiseTerms(fit), tau_s);
}

double AllanPoseMeanVariance(const AllanNoiseTerms& terms, double duration_s) {
  return ModelAllanVariance(terms, duration_s);
}

}  // namespace accelcal
