#include "studies/allan_study.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/format.h"
#include "simulation/random.h"

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace accelcal {
namespace {

// Subnormal doubles flushed to 0 while in scope (x86's FTZ and DAZ): NoiseProcessAllanVariance's
// Gauss-Markov sums multiply phi^j on down to subnormals at the long taus (2m terms: 10^6 at
// m = 2^19), each product some hundred times slower, 0.7 s of a 2e6-sample still log's run. The
// sums do not change: what is flushed (below 2.2e-308) is below half an ulp of the terms (>= 1)
// it is added to.
class FlushSubnormals {
 public:
#if defined(__SSE2__)
  FlushSubnormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040); }
  ~FlushSubnormals() { _mm_setcsr(saved_); }

 private:
  const unsigned int saved_;
#endif
};

constexpr int kProducts = 6;  // ww, rr, gg, wr, wg, rg

// Cumulative sums of one unit process over one segment (empty when the process is not simulated).
std::vector<double> CumulativeSums(const std::vector<double>& y) {
  std::vector<double> sums(y.size() + 1, 0.0);
  for (size_t i = 0; i < y.size(); ++i) sums[i + 1] = sums[i] + y[i];
  return sums;
}

// The six Allan products (ww, rr, gg, wr, wg, rg) at cluster size m of the three processes whose
// cumulative sums over n samples are `sums`, each over the n - 2m + 1 differences (4 m <= n).
std::array<double, kProducts> Products(const std::array<std::vector<double>, 3>& sums, long long n,
                                       long long m) {
  std::array<double, kProducts> total{};
  for (long long k = 0; k + 2 * m <= n; ++k) {
    std::array<double, 3> d;
    for (int u = 0; u < 3; ++u) d[u] = sums[u][k + 2 * m] - 2.0 * sums[u][k + m] + sums[u][k];
    total[0] += d[0] * d[0];
    total[1] += d[1] * d[1];
    total[2] += d[2] * d[2];
    total[3] += d[0] * d[1];
    total[4] += d[0] * d[2];
    total[5] += d[1] * d[2];
  }
  return total;
}

// A segment longer than AllanBootstrapOptions::max_segment_samples, simulated in pieces (see
// "Long segments" in allan_study.h): per level, the block size b, the samples simulated, and the
// points it gives.
struct PieceLevel {
  long long block = 1;
  long long samples = 0;
  std::vector<size_t> points;
  std::array<NoiseProcessParameters, 3> unit;  // the unit processes at the block period
  // Per point of `points`: the unit processes' exact Allan variances at m / block samples.
  std::vector<std::array<double, 3>> expected;
};

// The levels of a segment of n samples, with their processes and expectations.
std::vector<PieceLevel> PieceLevels(const AllanCurve& curve,
                                    const std::array<NoiseProcessParameters, 3>& unit, long long n,
                                    long long piece) {
  std::vector<PieceLevel> levels;
  size_t next = 0;  // the first point not yet given a level
  while (next < curve.points.size() && AllanSegmentUsed(n, curve.points[next].cluster_samples)) {
    PieceLevel level;
    // The first level at the sample period; each next one at blocks of 1/8 of its first point's
    // cluster, so that every point has at least 8 blocks per cluster.
    if (!levels.empty()) level.block = std::max(1LL, curve.points[next].cluster_samples / 8);
    level.samples = std::min(piece, n / level.block);
    for (; next < curve.points.size(); ++next) {
      const long long m = curve.points[next].cluster_samples;
      if (!AllanSegmentUsed(n, m) || !AllanSegmentUsed(level.samples, m / level.block)) break;
      level.points.push_back(next);
    }
    if (level.points.empty()) break;  // cannot happen for piece >= 64: each level gives one
    level.unit = unit;
    const FlushSubnormals flush;
    for (NoiseProcessParameters& process : level.unit)
      process.sample_period_s = curve.sample_period_s * static_cast<double>(level.block);
    for (size_t i : level.points) {
      std::array<double, 3> expected;
      for (int u = 0; u < 3; ++u) {
        expected[u] =
            NoiseProcessAllanVariance(level.unit[u], curve.points[i].cluster_samples / level.block);
      }
      level.expected.push_back(expected);
    }
    levels.push_back(level);
  }
  return levels;
}

// The Allan variances of series s of the table simulated with the model `coefficients` (the
// quadratic form of allan_study.h).
class SimulatedSeries {
 public:
  SimulatedSeries(const AllanBootstrapTable& table, const std::array<double, 3>& coefficients)
      : table_(table), points_(table.cluster_samples.size()) {
    const double white2 = std::max(0.0, coefficients[0]);
    const double bank2 = table.bank_variance_per_b2 * std::max(0.0, coefficients[1]);
    const double walk2 = std::max(0.0, coefficients[2]);
    const double white = std::sqrt(white2), bank = std::sqrt(bank2), walk = std::sqrt(walk2);
    factor_ = {white2, walk2, bank2, 2.0 * white * walk, 2.0 * white * bank, 2.0 * walk * bank};
  }

  void AllanVariances(int s, std::vector<double>* avar) const {
    avar->resize(points_);
    for (size_t i = 0; i < points_; ++i) {
      const std::array<double, kProducts>& product = table_.products[s * points_ + i];
      double sum = 0.0;
      for (int k = 0; k < kProducts; ++k) sum += factor_[k] * product[k];
      (*avar)[i] = sum;
    }
  }

 private:
  const AllanBootstrapTable& table_;
  const size_t points_;
  std::array<double, kProducts> factor_;
};

// No flag fits fewer terms: the message says what the curve is, not a flag to try.
const char kSingularRefit[] =
    "a simulated series of the Allan bootstrap could not be fitted (singular): the Allan "
    "deviation of these segments cannot separate the white, bias-instability and random-walk "
    "terms (an output whose noise is below its quantisation step, or segments too short, give such "
    "a curve), so "
    "no interval can be computed from it";

// Whether F(c) of allan_study.h exceeds `level`: F(c) the fraction of refits of term j at or
// below the observed coefficient when the model is the data's best fit with coefficient j held
// at c. The count stops as soon as the answer is certain (most of the cost is the refits).
class TailFraction {
 public:
  TailFraction(const AllanFitter& fitter, const AllanBootstrapTable& table,
               const std::vector<double>& avar, int j, double observed)
      : fitter_(fitter), table_(table), avar_(avar), j_(j), observed_(observed) {}

  Status Exceeds(double c, double level, bool* exceeds) const {
    std::array<double, 3> model;
    if (!fitter_.Fit(avar_.data(), &model, j_, c))
      return Status::Error(
          "the Allan fit with one term held is singular: the Allan deviation of these segments "
          "cannot separate the white, bias-instability and random-walk terms (an output "
          "quantised below its noise, or segments too short, give such a curve), so no "
          "interval can be computed from it");
    const SimulatedSeries simulated(table_, model);
    const double needed = level * table_.series;  // exceeds when the count is above this
    std::vector<double> avar;
    std::array<double, 3> refit;
    int at_or_below = 0;
    for (int s = 0; s < table_.series; ++s) {
      if (at_or_below > needed || at_or_below + (table_.series - s) <= needed) break;
      simulated.AllanVariances(s, &avar);
      if (!fitter_.Fit(avar.data(), &refit)) return Status::Error(kSingularRefit);
      at_or_below += refit[j_] <= observed_;
    }
    *exceeds = at_or_below > needed;
    return Status::Ok();
  }

 private:
  const AllanFitter& fitter_;
  const AllanBootstrapTable& table_;
  const std::vector<double>& avar_;
  const int j_;
  const double observed_;
};

// The c >= 0 where F(c) falls to `level` (F decreasing), given F(0) > level: doubling from
// `scale` to bracket it, then bisection to a relative 3e-3 (0.15% of the term).
Status Crossing(const TailFraction& tail, double level, double scale, double* c) {
  double low = 0.0, high = scale;
  bool exceeds = false;
  for (int doubling = 0;; ++doubling) {
    ACCELCAL_RETURN_IF_ERROR(tail.Exceeds(high, level, &exceeds));
    if (!exceeds) break;
    if (doubling == 200) {
      return Status::Error(
          "the bootstrap found no upper bound for a noise term: its Allan variance points do "
          "not constrain it (segments too short for the term's time scale)");
    }
    low = high;
    high *= 2.0;
  }
  while (high - low > 3e-3 * high) {
    const double middle = 0.5 * (low + high);
    ACCELCAL_RETURN_IF_ERROR(tail.Exceeds(middle, level, &exceeds));
    (exceeds ? low : high) = middle;
  }
  *c = 0.5 * (low + high);
  return Status::Ok();
}

// One segment of n samples, longer than max_segment_samples, into `products` (as the loop of
// MakeAllanBootstrapTable adds a segment simulated whole: its share of each point's differences
// times its Allan products): per level, `piece` samples at most of the unit processes at the
// level's block period, each point's products normalised by their expectation at that period,
// moved towards 1 by sqrt(f) (f: the piece's share of the segment's differences at that
// resolution) and scaled by the expectation at the sample period (`expected`).
void AddPieces(const AllanCurve& curve, const std::vector<PieceLevel>& levels,
               const std::vector<std::array<double, kProducts>>& expected, long long n,
               RandomSource* random, std::array<double, kProducts>* products) {
  for (const PieceLevel& level : levels) {
    std::array<std::vector<double>, 3> sums;
    for (int u = 0; u < 3; ++u)
      sums[u] = CumulativeSums(SimulateNoiseProcess(level.unit[u], level.samples, random));
    const long long whole = n / level.block;  // the segment's samples at this resolution
    for (size_t point = 0; point < level.points.size(); ++point) {
      const size_t i = level.points[point];
      const long long m = curve.points[i].cluster_samples;
      const long long mc = m / level.block;
      const std::array<double, kProducts> total = Products(sums, level.samples, mc);
      const double differences = static_cast<double>(level.samples - 2 * mc + 1);
      const double f = differences / static_cast<double>(whole - 2 * mc + 1);
      std::array<double, 3> ratio{};  // simulated over expected, per process, and its scale
      std::array<double, 3> scale{};
      for (int u = 0; u < 3; ++u) {
        const double at_block = level.expected[point][u];
        const double mean = total[u] / (2.0 * static_cast<double>(mc * mc) * differences);
        ratio[u] = at_block > 0.0 ? mean / at_block : 1.0;
        scale[u] = at_block > 0.0 ? std::sqrt(expected[i][u] / at_block) : 0.0;
      }
      std::array<double, kProducts> product;
      for (int u = 0; u < 3; ++u)
        product[u] = expected[i][u] * (1.0 + std::sqrt(f) * (ratio[u] - 1.0));
      const std::array<std::array<int, 2>, 3> pairs = {{{0, 1}, {0, 2}, {1, 2}}};
      for (int p = 0; p < 3; ++p) {
        const int a = pairs[p][0], b = pairs[p][1];
        const double mean = total[3 + p] / (2.0 * static_cast<double>(mc * mc) * differences);
        product[3 + p] = std::sqrt(f) * mean * scale[a] * scale[b];
      }
      // This segment's share of the point's differences, as a segment simulated whole adds.
      const double share = static_cast<double>(n - 2 * m + 1) /
                           static_cast<double>(curve.points[i].difference_count);
      for (int k = 0; k < kProducts; ++k) products[i][k] += share * product[k];
    }
  }
}

Status CheckTable(const AllanCurve& curve, const AllanBootstrapTable& table) {
  bool same = table.sample_period_s == curve.sample_period_s &&
              table.segment_samples == curve.segment_samples &&
              table.cluster_samples.size() == curve.points.size() && table.series > 0 &&
              table.products.size() == table.cluster_samples.size() * table.series;
  for (size_t i = 0; same && i < curve.points.size(); ++i)
    same = table.cluster_samples[i] == curve.points[i].cluster_samples;
  if (!same) {
    return Status::Error(
        "the Allan bootstrap table was made for other segments or taus than this curve's");
  }
  return Status::Ok();
}

}  // namespace

std::vector<NoiseProcessParameters::Markov> AllanBiasInstabilityBank(const AllanCurve& curve,
                                                                     double* variance_per_b2) {
  std::vector<NoiseProcessParameters::Markov> bank;
  *variance_per_b2 = 0.0;
  if (curve.points.empty()) return bank;
  const double tau_max_s = curve.points.back().tau_s;
  for (double t_c = curve.sample_period_s / 2.0; t_c <= 2.0 * tau_max_s; t_c *= 4.0)
    bank.push_back({1.0, t_c});
  // The bank's unit-q Allan variance at the middle cluster size, against the fitted floor's.
  NoiseProcessParameters unit;
  unit.sample_period_s = curve.sample_period_s;
  unit.markov = bank;
  const long long middle = curve.points[curve.points.size() / 2].cluster_samples;
  *variance_per_b2 =
      BiasInstabilityFactor() * BiasInstabilityFactor() / NoiseProcessAllanVariance(unit, middle);
  return bank;
}

NoiseProcessParameters AllanModelProcess(const AllanNoiseTerms& terms, const AllanCurve& curve) {
  NoiseProcessParameters process;
  process.sample_period_s = curve.sample_period_s;
  process.white_density = terms.white_density;
  process.random_walk = terms.random_walk;
  if (terms.bias_instability > 0.0) {
    double variance_per_b2 = 0.0;
    process.markov = AllanBiasInstabilityBank(curve, &variance_per_b2);
    const double q = std::sqrt(variance_per_b2) * terms.bias_instability;
    for (NoiseProcessParameters::Markov& markov : process.markov) markov.stddev = q;
  }
  return process;
}

Status MakeAllanBootstrapTable(const AllanOptions& options, const AllanCurve& curve,
                               const AllanBootstrapOptions& bootstrap, AllanBootstrapTable* table) {
  if (bootstrap.series < 100) {
    return Status::Error(StringPrintf(
        "a bootstrap of %d series cannot place 2.5%% tails; give at least 100 (1000 advised)",
        bootstrap.series));
  }
  *table = AllanBootstrapTable();
  table->sample_period_s = curve.sample_period_s;
  table->segment_samples = curve.segment_samples;
  for (const AllanPoint& point : curve.points)
    table->cluster_samples.push_back(point.cluster_samples);
  table->series = bootstrap.series;
  // The three unit processes, each simulated only when its term is fitted.
  std::array<NoiseProcessParameters, 3> unit;
  for (NoiseProcessParameters& process : unit) process.sample_period_s = curve.sample_period_s;
  if (options.fit_white) unit[0].white_density = 1.0;
  if (options.fit_random_walk) unit[1].random_walk = 1.0;
  const std::vector<NoiseProcessParameters::Markov> bank =
      AllanBiasInstabilityBank(curve, &table->bank_variance_per_b2);
  if (options.fit_bias_instability) unit[2].markov = bank;
  const size_t points = curve.points.size();
  // The segments a series simulates: all of them, or beyond the cap (see "Long data") the
  // longest and every k-th of the others.
  const std::vector<long long>& segments = curve.segment_samples;
  std::vector<size_t> simulated(segments.size());
  for (size_t j = 0; j < segments.size(); ++j) simulated[j] = j;
  long long total = 0;
  for (long long n : segments) total += n;
  if (total > bootstrap.max_simulated_samples && segments.size() > 1) {
    const size_t longest =
        static_cast<size_t>(std::max_element(segments.begin(), segments.end()) - segments.begin());
    const long long others = total - segments[longest];
    const long long cap = std::max(1LL, bootstrap.max_simulated_samples);
    for (size_t stride = static_cast<size_t>(std::max(2LL, others / cap));; ++stride) {
      simulated = {longest};
      long long kept = segments[longest];
      for (size_t j = 0, other = 0; j < segments.size(); ++j) {
        if (j == longest) continue;
        if (other++ % stride == 0) {
          simulated.push_back(j);
          kept += segments[j];
        }
      }
      if (kept <= bootstrap.max_simulated_samples + segments[longest] || simulated.size() <= 1)
        break;
    }
    std::sort(simulated.begin(), simulated.end());
  }
  // Per point: the share of its differences simulated, and the products' expectations.
  std::vector<double> share(points, 1.0);
  std::vector<std::array<double, kProducts>> expected(points);
  for (size_t i = 0; i < points; ++i) {
    const long long m = curve.points[i].cluster_samples;
    long long differences = 0;
    for (size_t j : simulated)
      if (AllanSegmentUsed(segments[j], m)) differences += segments[j] - 2 * m + 1;
    share[i] =
        static_cast<double>(differences) / static_cast<double>(curve.points[i].difference_count);
    expected[i] = {};
    const FlushSubnormals flush;
    for (int u = 0; u < 3; ++u) expected[i][u] = NoiseProcessAllanVariance(unit[u], m);
  }
  // The levels of the segments simulated in pieces (see "Long segments").
  std::vector<std::vector<PieceLevel>> pieces(segments.size());
  for (size_t j : simulated) {
    if (segments[j] > bootstrap.max_segment_samples)
      pieces[j] = PieceLevels(curve, unit, segments[j], bootstrap.piece_samples);
  }
  table->products.assign(points * bootstrap.series, {});
  for (int s = 0; s < bootstrap.series; ++s) {
    RandomSource random(bootstrap.seed, static_cast<uint64_t>(s));
    std::array<double, kProducts>* products = &table->products[s * points];
    for (size_t j : simulated) {
      const long long n = segments[j];
      if (n > bootstrap.max_segment_samples) {
        AddPieces(curve, pieces[j], expected, n, &random, products);
        continue;
      }
      std::array<std::vector<double>, 3> sums;
      for (int u = 0; u < 3; ++u)
        sums[u] = CumulativeSums(SimulateNoiseProcess(unit[u], n, &random));
      for (size_t i = 0; i < points; ++i) {
        const long long m = curve.points[i].cluster_samples;
        if (4 * m > n) continue;
        const std::array<double, kProducts> total = Products(sums, n, m);
        const double scale = 1.0 / (2.0 * static_cast<double>(m) * static_cast<double>(m) *
                                    static_cast<double>(curve.points[i].difference_count));
        for (int k = 0; k < kProducts; ++k) products[i][k] += scale * total[k];
      }
    }
    if (simulated.size() == segments.size()) continue;
    // Over the simulated differences only, then moved to the data's variance.
    for (size_t i = 0; i < points; ++i) {
      for (int k = 0; k < kProducts; ++k) {
        const double mean_simulated = products[i][k] / share[i];
        products[i][k] = expected[i][k] + std::sqrt(share[i]) * (mean_simulated - expected[i][k]);
      }
    }
  }
  return Status::Ok();
}

Status FitAllanNoiseWithBootstrap(const AllanOptions& options, const AllanBootstrapTable& table,
                                  AllanCurve* curve, AllanNoiseFit* fit) {
  ACCELCAL_RETURN_IF_ERROR(FitAllanNoise(options, curve, fit));
  ACCELCAL_RETURN_IF_ERROR(CheckTable(*curve, table));
  const AllanFitter fitter(options, *curve);
  std::vector<double> avar;
  for (const AllanPoint& point : curve->points) avar.push_back(point.avar);
  std::array<double, 3> base;
  for (int j = 0; j < 3; ++j) base[j] = std::max(0.0, fit->coefficients[j]);
  // The spread of the refits at the fitted model: the terms' sigmas, the coefficients'
  // covariance.
  const SimulatedSeries simulated(table, base);
  std::vector<std::array<double, 3>> refits(table.series);
  std::vector<double> simulated_avar, weights;
  int chi2_at_least = 0;
  for (int s = 0; s < table.series; ++s) {
    simulated.AllanVariances(s, &simulated_avar);
    if (!fitter.Fit(simulated_avar.data(), &refits[s], -1, 0.0, &weights))
      return Status::Error(kSingularRefit);
    chi2_at_least += fitter.Chi2(simulated_avar.data(), refits[s], weights) >= fit->chi2;
  }
  fit->chi2_bootstrap_fraction = static_cast<double>(chi2_at_least) / table.series;
  std::array<double, 3> mean{};
  for (const std::array<double, 3>& c : refits)
    for (int j = 0; j < 3; ++j) mean[j] += c[j] / static_cast<double>(refits.size());
  fit->covariance = {};
  for (const std::array<double, 3>& c : refits) {
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k)
        fit->covariance[r][k] +=
            (c[r] - mean[r]) * (c[k] - mean[k]) / static_cast<double>(refits.size() - 1);
  }
  fit->covariance_method = "parametric bootstrap";
  fit->bootstrap_series = table.series;
  SetAllanTermsFromCovariance(options, fit);
  // The intervals by test inversion, in place of SetAllanTermsFromCovariance's normal ones.
  const double alpha = 1.0 - options.confidence;
  AllanTerm* terms[3] = {&fit->white, &fit->bias_instability, &fit->random_walk};
  for (int j = 0; j < 3; ++j) {
    AllanTerm& term = *terms[j];
    if (!term.fitted) continue;
    const double observed = fit->coefficients[j];
    const TailFraction tail(fitter, table, avar, j, observed);
    const double scale = std::max({std::fabs(observed), std::sqrt(fit->covariance[j][j]), 1e-300});
    bool above_low = false, above_high = false;  // F(0) > alpha/2, F(0) > 1 - alpha/2
    ACCELCAL_RETURN_IF_ERROR(tail.Exceeds(0.0, alpha / 2.0, &above_low));
    ACCELCAL_RETURN_IF_ERROR(tail.Exceeds(0.0, 1.0 - alpha / 2.0, &above_high));
    double low = 0.0, high = 0.0;
    if (above_low) ACCELCAL_RETURN_IF_ERROR(Crossing(tail, alpha / 2.0, scale, &high));
    if (above_high) ACCELCAL_RETURN_IF_ERROR(Crossing(tail, 1.0 - alpha / 2.0, scale, &low));
    term.resolved = low > 0.0;
    term.below_model = !above_low;
    term.low = std::sqrt(low);
    term.high = std::sqrt(high);
    if (!term.resolved) term.stddev = 0.0;
  }
  return Status::Ok();
}

Status FitAllanNoiseWithBootstrap(const AllanOptions& options,
                                  const AllanBootstrapOptions& bootstrap, AllanCurve* curve,
                                  AllanNoiseFit* fit) {
  AllanBootstrapTable table;
  ACCELCAL_RETURN_IF_ERROR(MakeAllanBootstrapTable(options, *curve, bootstrap, &table));
  return FitAllanNoiseWithBootstrap(options, table, curve, fit);
}

}  // namespace accelcal
