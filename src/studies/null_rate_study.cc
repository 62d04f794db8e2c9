#include "studies/null_rate_study.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/format.h"
#include "estimation/tilt_table/discovery.h"
#include "models/effects.h"
#include "simulation/monte_carlo.h"

namespace accelcal {
namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr int kDesignSamples = 2000;

// splitmix64's finaliser: nearby inputs give unrelated outputs.
uint64_t Mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// FNV-1a: a design's key from its name, so adding a design does not move the others' data.
uint64_t NameKey(const std::string& name) {
  uint64_t hash = 0xcbf29ce484222325ULL;
  for (const char c : name) hash = (hash ^ static_cast<unsigned char>(c)) * 0x100000001b3ULL;
  return hash;
}

uint64_t DatasetStream(const std::string& design, double noise_factor, int dataset) {
  uint64_t factor_bits;
  std::memcpy(&factor_bits, &noise_factor, sizeof(factor_bits));
  return Mix(Mix(Mix(NameKey(design)) ^ factor_bits) ^ static_cast<uint64_t>(dataset));
}

// What one dataset got at one alpha.
struct Outcome {
  bool error = false;
  Verdict verdict = Verdict::kExplained;
  std::vector<std::string> effects;
  std::vector<std::string> noise_findings;
  std::vector<std::string> checks;
};

Outcome Summarize(const Status& status, const DiscoveryResult& result) {
  Outcome outcome;
  if (!status.ok()) {
    outcome.error = true;
    return outcome;
  }
  outcome.verdict = result.verdict_code;
  for (const DiscoveredEffect& effect : result.effects)
    outcome.effects.push_back(Info(effect.effect).name);
  for (const NoiseFinding& finding : result.noise_findings)
    outcome.noise_findings.push_back(NoiseFindingName(finding.kind));
  for (const ResidualCheck& check : result.checks) {
    if (check.flagged) outcome.checks.push_back(check.name);
  }
  return outcome;
}

// Counts each name once per dataset.
void CountNames(const std::vector<std::string>& names, std::map<std::string, int>* counts) {
  std::vector<std::string> unique = names;
  std::sort(unique.begin(), unique.end());
  unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
  for (const std::string& name : unique) ++(*counts)[name];
}

void AddOutcome(const Outcome& outcome, NullRateCell* cell) {
  ++cell->datasets;
  if (outcome.error) {
    ++cell->errors;
    return;
  }
  ++cell->verdicts;
  ++cell->verdict_counts[VerdictCode(outcome.verdict)];
  if (outcome.verdict != Verdict::kExplained) ++cell->not_explained;
  if (!outcome.effects.empty()) ++cell->with_effects;
  if (!outcome.noise_findings.empty()) ++cell->with_noise_findings;
  if (!outcome.checks.empty()) ++cell->with_flagged_checks;
  if (outcome.verdict == Verdict::kCannotTellApart) ++cell->cannot_tell_apart;
  CountNames(outcome.effects, &cell->effects_named);
  CountNames(outcome.noise_findings, &cell->noise_findings_named);
  CountNames(outcome.checks, &cell->checks_flagged);
}

PooledNullRate Pool(double alpha, const std::vector<NullRateCell>& cells) {
  PooledNullRate pooled;
  pooled.alpha = alpha;
  for (const NullRateCell& cell : cells) {
    if (cell.alpha != alpha) continue;
    pooled.verdicts += cell.verdicts;
    pooled.errors += cell.errors;
    pooled.not_explained += cell.not_explained;
  }
  const double n = std::max(pooled.verdicts, 1);
  pooled.rate = pooled.not_explained / n;
  pooled.rate_stddev = std::sqrt(pooled.rate * (1.0 - pooled.rate) / n);
  pooled.alpha_stddev = std::sqrt(alpha * (1.0 - alpha) / n);
  pooled.bound = alpha + 2.0 * pooled.alpha_stddev;
  pooled.within = pooled.verdicts > 0 && pooled.rate <= pooled.bound;
  return pooled;
}

}  // namespace

const std::vector<std::string>& NullRateDesignNames() {
  static const std::vector<std::string> names = {"course", "n2000", "eight_positions",
                                                 "half_circle"};
  return names;
}

std::string NullRateDesignDescription(const std::string& name) {
  if (name == "course") return "the scenario's own tilt test";
  if (name == "n2000") return "2000 samples uniform over [0, 2 pi)";
  if (name == "eight_positions") return "2000 samples at 8 static positions 2 pi k / 8";
  if (name == "half_circle") return "2000 samples uniform over [0, pi]";
  return "";
}

Status MakeNullScenario(const Scenario& course, const std::string& name, double noise_factor,
                        Scenario* scenario) {
  if (!(std::isfinite(noise_factor) && noise_factor > 0.0)) {
    return Status::Error("noise factor " + RoundTripDouble(noise_factor) +
                         " is not a finite positive number");
  }
  Scenario null = course;
  TiltSchedule& tilt = null.tilt;
  if (name == "course") {
    // As loaded.
  } else if (name == "n2000") {
    // kUniform includes both ends; 2 pi itself would repeat theta = 0.
    tilt = TiltSchedule();
    tilt.kind = TiltSchedule::Kind::kUniform;
    tilt.sample_count = kDesignSamples;
    tilt.theta_begin_rad = 0.0;
    tilt.theta_end_rad = kTwoPi * (kDesignSamples - 1) / kDesignSamples;
  } else if (name == "eight_positions") {
    tilt = TiltSchedule();
    tilt.kind = TiltSchedule::Kind::kStaticPositions;
    tilt.sample_count = kDesignSamples;
    for (int k = 0; k < 8; ++k) tilt.positions_rad.push_back(kTwoPi * k / 8.0);
  } else if (name == "half_circle") {
    tilt = TiltSchedule();
    tilt.kind = TiltSchedule::Kind::kUniform;
    tilt.sample_count = kDesignSamples;
    tilt.theta_begin_rad = 0.0;
    tilt.theta_end_rad = kTwoPi / 2.0;
  } else {
    std::string known;
    for (const std::string& design : NullRateDesignNames())
      known += (known.empty() ? "" : ", ") + design;
    return Status::Error("unknown design '" + name.substr(0, 40) + "' (known: " + known + ")");
  }
  // The scenario may hide effects or disturbances (a file, --set); the null has none.
  for (const ParameterInfo& info : ParameterCatalogue()) {
    if (!info.baseline) null.truth.parameters[info.parameter] = info.neutral;
  }
  null.truth.disturbances = Disturbances();
  null.truth.stated_noise_variance_x *= noise_factor;
  null.truth.stated_noise_variance_y *= noise_factor;
  *scenario = null;
  return Status::Ok();
}

Status RunNullRateStudy(const Scenario& course, const NullRateOptions& options,
                        NullRateResult* result) {
  if (options.datasets < 1) return Status::Error("datasets must be at least 1");
  if (options.alphas.empty() || options.designs.empty() || options.noise_factors.empty())
    return Status::Error("no design, noise factor or alpha to study");
  for (const double alpha : options.alphas) {
    if (!(alpha > 0.0 && alpha < 0.5))
      return Status::Error("alpha " + RoundTripDouble(alpha) + " is not in (0, 0.5)");
  }
  // A repeated design, factor or alpha would count the same datasets twice in the pool.
  auto repeats = [](auto values) {
    std::sort(values.begin(), values.end());
    return std::adjacent_find(values.begin(), values.end()) != values.end();
  };
  if (repeats(options.designs) || repeats(options.noise_factors) || repeats(options.alphas))
    return Status::Error("a design, noise factor or alpha is listed twice");
  // Every scenario first, so a bad name fails before minutes of work.
  std::vector<Scenario> scenarios;
  for (const std::string& design : options.designs) {
    for (const double factor : options.noise_factors) {
      scenarios.emplace_back();
      ACCELCAL_RETURN_IF_ERROR(MakeNullScenario(course, design, factor, &scenarios.back()));
    }
  }

  *result = NullRateResult();
  double seconds = 0.0;
  int threads = 1;
  const int alpha_count = static_cast<int>(options.alphas.size());
  size_t next_scenario = 0;
  ProgressCounter progress(options.progress,
                           static_cast<int64_t>(scenarios.size()) * options.datasets);
  for (const std::string& design : options.designs) {
    for (const double factor : options.noise_factors) {
      const Scenario& scenario = scenarios[next_scenario++];
      // outcomes[dataset * alpha_count + a]: each trial writes only its own slots.
      std::vector<Outcome> outcomes(static_cast<size_t>(options.datasets) * alpha_count);
      MonteCarloOptions monte_carlo;
      monte_carlo.trials = options.datasets;
      monte_carlo.threads = options.threads;
      monte_carlo.progress = &progress;
      const MonteCarloTiming timing = RunTrials(monte_carlo, [&](int dataset) {
        const SimulatedData data =
            SimulateScenario(scenario, options.seed, DatasetStream(design, factor, dataset));
        for (int a = 0; a < alpha_count; ++a) {
          DiscoveryOptions discovery;
          discovery.alpha = options.alphas[a];
          discovery.gravity_mps2 = scenario.truth.gravity_mps2;
          // Cross-validation only describes the extended model; the verdict does not use it.
          discovery.cross_validation_folds = 0;
          // The trials already fill the cores.
          discovery.num_threads = 1;
          DiscoveryResult discovered;
          const Status status = Discover(data.test, data.run, data.conditions, data.landmarks,
                                         discovery, &discovered);
          outcomes[static_cast<size_t>(dataset) * alpha_count + a] = Summarize(status, discovered);
        }
      });
      seconds += timing.seconds;
      threads = timing.threads;
      for (int a = 0; a < alpha_count; ++a) {
        NullRateCell cell;
        cell.design = design;
        cell.noise_factor = factor;
        cell.alpha = options.alphas[a];
        for (int dataset = 0; dataset < options.datasets; ++dataset)
          AddOutcome(outcomes[static_cast<size_t>(dataset) * alpha_count + a], &cell);
        cell.rate =
            cell.verdicts > 0 ? static_cast<double>(cell.not_explained) / cell.verdicts : 0.0;
        result->cells.push_back(std::move(cell));
      }
    }
  }
  for (const double alpha : options.alphas) result->pooled.push_back(Pool(alpha, result->cells));
  result->seconds = seconds;
  result->threads = threads;
  return Status::Ok();
}

}  // namespace accelcal
