#include "estimation/discovery/selection.h"

#include <algorithm>
#include <cmath>

#include "estimation/statistics/chi_square.h"
#include "estimation/statistics/diagnostics.h"

namespace accelcal {

int WeakestNotNeeded(const std::vector<double>& p_values, double alpha) {
  const std::vector<bool> needed = HolmRejections(p_values, alpha);
  int weakest = -1;
  for (size_t e = 0; e < p_values.size(); ++e) {
    if (!needed[e] && (weakest < 0 || p_values[e] > p_values[weakest]))
      weakest = static_cast<int>(e);
  }
  return weakest;
}

Status SelectEffects(DiscoveryGeometry* geometry, std::vector<int> candidates,
                     const SelectionOptions& options, SelectionRecord* record) {
  int step = options.first_step;
  for (bool changed = true; changed;) {
    changed = false;
    // Forward selection over the candidates left (numbering on from the last step scored).
    if (!record->scores.empty()) step = record->scores.back().step + 1;
    for (;
         !candidates.empty() && static_cast<int>(geometry->Effects().size()) < options.max_effects;
         ++step) {
      std::vector<CandidateTest> tests;
      ACCELCAL_RETURN_IF_ERROR(geometry->TestCandidates(candidates, &tests));
      // A candidate that cannot be tested leaves the candidates, with why.
      std::vector<int> tested;
      std::vector<CandidateTest> tested_tests;
      for (size_t c = 0; c < candidates.size(); ++c) {
        if (tests[c].tested) {
          tested.push_back(candidates[c]);
          tested_tests.push_back(tests[c]);
        } else {
          record->not_tested.push_back({candidates[c], tests[c].not_tested});
        }
      }
      candidates = tested;
      if (candidates.empty()) break;
      std::vector<double> p_values;
      for (const CandidateTest& test : tested_tests) p_values.push_back(test.p_value);
      const std::vector<bool> significant = HolmRejections(p_values, options.alpha);
      // The most significant rejected; of equal p-values, the one that removes more.
      int best = -1;
      for (size_t c = 0; c < candidates.size(); ++c) {
        record->scores.push_back(
            {step, candidates[c], tested_tests[c].delta_chi2, p_values[c], significant[c]});
        if (significant[c] && (best < 0 || p_values[c] < p_values[best] ||
                               (p_values[c] == p_values[best] &&
                                tested_tests[c].delta_chi2 > tested_tests[best].delta_chi2)))
          best = static_cast<int>(c);
      }
      if (best < 0) break;
      const int chosen = candidates[best];
      candidates.erase(candidates.begin() + best);
      double delta_chi2 = 0.0;
      // Not separable from what is already in the model: it leaves the candidates.
      if (!geometry->Add(chosen, &delta_chi2).ok()) continue;
      record->history.push_back({true, step, chosen, delta_chi2, p_values[best]});
    }
    // Backward elimination against the grown model.
    while (!geometry->Effects().empty()) {
      std::vector<CandidateTest> tests;
      ACCELCAL_RETURN_IF_ERROR(geometry->TestEffects(&tests));
      std::vector<double> p_values;
      for (const CandidateTest& test : tests) p_values.push_back(test.p_value);
      const int weakest = WeakestNotNeeded(p_values, options.alpha);
      if (weakest < 0) break;
      record->history.push_back({false, step, geometry->Effects()[weakest],
                                 tests[weakest].delta_chi2, p_values[weakest]});
      ACCELCAL_RETURN_IF_ERROR(geometry->Drop(weakest));
      changed = true;
    }
  }
  return Status::Ok();
}

namespace {

std::vector<int> NotInModel(const DiscoveryGeometry& geometry, const std::vector<int>& candidates) {
  const std::vector<int>& model = geometry.Effects();
  std::vector<int> others;
  for (const int candidate : candidates) {
    if (std::find(model.begin(), model.end(), candidate) == model.end())
      others.push_back(candidate);
  }
  return others;
}

}  // namespace

std::vector<SwappedModel> FitSwaps(DiscoveryGeometry* geometry,
                                   const std::vector<int>& candidates) {
  const std::vector<int> others = NotInModel(*geometry, candidates);
  std::vector<SwappedModel> swaps;
  for (size_t e = 0; e < geometry->Effects().size(); ++e) {
    for (const int candidate : others) {
      SwappedModel swap{e, candidate, {}};
      if (geometry->Swap(e, candidate, &swap.fit)) swaps.push_back(std::move(swap));
    }
  }
  return swaps;
}

std::vector<LookAlike> FindLookAlikes(const DiscoveryGeometry& geometry,
                                      const std::vector<int>& candidates,
                                      const std::vector<SwappedModel>& swaps,
                                      const std::vector<double>& effect_delta_chi2) {
  const size_t alternatives = NotInModel(geometry, candidates).size();
  std::vector<LookAlike> look_alikes;
  for (const SwappedModel& swap : swaps) {
    if (geometry.LooksAlike(swap.effect, swap.fit, effect_delta_chi2[swap.effect], alternatives))
      look_alikes.push_back(swap);
  }
  return look_alikes;
}

std::vector<Partner> FindPartners(DiscoveryGeometry* geometry, const std::vector<int>& candidates,
                                  const std::vector<SwappedModel>& swaps,
                                  const std::vector<double>& effect_delta_chi2,
                                  const PartnerOptions& options) {
  const size_t model_size = geometry->Effects().size();
  std::vector<Partner> partners;
  const auto complete = [model_size](const AlternativeFit& fit) {
    return fit.current_estimates.size() == model_size && fit.current_stddevs.size() == model_size &&
           fit.estimates.size() == model_size && fit.stddevs.size() == model_size;
  };
  const auto shift_of = [](const AlternativeFit& fit, size_t e) {
    return std::abs(fit.estimates[e] - fit.current_estimates[e]) / fit.current_stddevs[e];
  };
  for (const int candidate : NotInModel(*geometry, candidates)) {
    BesideFit fit;
    if (!geometry->Beside(candidate, &fit) || !complete(fit)) continue;
    const double p_value = ChiSquareSurvival(std::max(0.0, fit.gain), 1.0);
    for (size_t e = 0; e < model_size; ++e) {
      if (!(fit.current_stddevs[e] > 0.0)) continue;
      const double shift = shift_of(fit, e);
      const double r = fit.stddevs[e] / fit.current_stddevs[e];
      const double reach = shift + std::sqrt(std::max(0.0, r * r - 1.0));
      if ((p_value <= options.alpha && shift >= options.shift_sigma) ||
          reach >= options.reach_sigma)
        partners.push_back({e, candidate, -1, fit, -fit.gain, p_value, shift, reach});
    }
  }
  for (const SwappedModel& swap : swaps) {
    const SwapFit& fit = swap.fit;
    if (!complete(fit) || !geometry->FitsAboutAsWell(fit)) continue;
    const double explained = std::max(0.0, effect_delta_chi2[swap.effect] - fit.worse);
    const double p_value = ChiSquareSurvival(explained, 1.0);
    if (!(p_value <= options.alpha)) continue;
    // Each effect kept it moves (the slot it replaces is not judged).
    for (size_t e = 0; e < model_size; ++e) {
      if (e == swap.effect || !(fit.current_stddevs[e] > 0.0)) continue;
      const double shift = shift_of(fit, e);
      if (shift >= options.shift_sigma)
        partners.push_back({e, swap.alternative, static_cast<int>(swap.effect), fit, fit.worse,
                            p_value, shift, 0.0});
    }
  }
  return partners;
}

Verdict DecideVerdict(bool structure_remains, bool look_alikes, bool found) {
  if (structure_remains) return Verdict::kUnexplained;
  if (look_alikes) return Verdict::kCannotTellApart;
  if (found) return Verdict::kMissing;
  return Verdict::kExplained;
}

}  // namespace accelcal
