#ifndef ACCELCAL_ESTIMATION_DISCOVERY_SELECTION_H_
#define ACCELCAL_ESTIMATION_DISCOVERY_SELECTION_H_

// The part of discovery that is the same for every sensor geometry, written once (issue 31):
// which effects of the catalogue the data need, added one at a time and re-tested once the model
// has grown (SelectEffects); which other candidates could stand in for an effect found
// (FindLookAlikes); and the verdict those steps and the checks of what remains give
// (DecideVerdict). A geometry (the tilt table's joint fit, estimation/tilt_table/discovery.cc;
// the triad's fit of pose means, estimation/triad/triad_discovery.cc; the gyroscope's, to come)
// implements DiscoveryGeometry: how its model is fitted with a set of candidate effects, and how
// one candidate is tested against it (a score test and chi-square(1), or a refit and an F test).
// Its own noise step and checks of what remains stay with it (their statistics are
// estimation/statistics/ and estimation/discovery/check.h).
//
// Forward selection at `alpha` (the procedure's share for effects): every candidate left is
// tested against the current model, Holm over those tested, the most significant of those
// rejected is added (when its model cannot be fitted it is not separable from the model: it
// leaves the candidates and the step is spent), until none is rejected or `max_effects` are in
// the model. Backward elimination: every effect of the grown model is tested against the model
// without it, Holm at `alpha` over the model's effects, and the weakest one not needed is dropped;
// forward and backward alternate until neither changes the model (an effect dropped is not
// offered again, so it ends). A candidate that cannot be tested (its fit fails, or it would leave
// no degree of freedom) leaves the candidates, listed with why.

#include <string>
#include <vector>

#include "common/status.h"
#include "estimation/discovery/verdict.h"

namespace accelcal {

// One candidate tested against a model: the chi-square it removes from it (or, for an effect of
// the model, what the model loses without it) and its p-value; or why it is not tested.
struct CandidateTest {
  bool tested = true;
  double delta_chi2 = 0.0;
  double p_value = 1.0;
  std::string not_tested;  // why, when !tested
};

// A model with a candidate in it, fitted as an alternative to the current one and not kept:
// the candidate's estimate, and the current model's effects (Effects() order) as fitted and in
// it. The vectors are empty when the geometry does not give them (then FindPartners finds no
// partner in that model).
struct AlternativeFit {
  double estimate = 0.0;  // the candidate's
  double stddev = 0.0;
  std::vector<double> current_estimates, current_stddevs;
  std::vector<double> estimates, stddevs;
  std::string note;  // what else differs in it, in words (the tilt table's tie)
};

// The model with one effect replaced by another candidate (the replaced effect's slot holds its
// value as fitted in both vectors).
struct SwapFit : AlternativeFit {
  double worse = 0.0;  // its chi-square minus the current model's
};

// The current model grown by one candidate beside its effects.
struct BesideFit : AlternativeFit {
  double gain = 0.0;  // the chi-square the candidate removes
};

// What a sensor geometry gives the procedure. Candidates are indices into the geometry's own
// list; the geometry holds the current model and its fit.
class DiscoveryGeometry {
 public:
  virtual ~DiscoveryGeometry() = default;
  // Each of `candidates` added to the current model, tested.
  virtual Status TestCandidates(const std::vector<int>& candidates,
                                std::vector<CandidateTest>* tests) = 0;
  // The current model grown by `candidate` and fitted; `*delta_chi2`: the chi-square it removed.
  // Fails, leaving the model as it was, when the grown model cannot be fitted.
  virtual Status Add(int candidate, double* delta_chi2) = 0;
  // Each effect of the current model (in Effects() order), tested against the model without it.
  virtual Status TestEffects(std::vector<CandidateTest>* tests) = 0;
  // The current model without its effect `effect` (an index into Effects()), refitted.
  virtual Status Drop(size_t effect) = 0;
  // The current model's effects, as candidate indices.
  virtual const std::vector<int>& Effects() const = 0;
  // The current model with its effect `effect` replaced by `candidate`, fitted; false when it
  // cannot be fitted.
  virtual bool Swap(size_t effect, int candidate, SwapFit* fit) = 0;
  // Whether the swapped model fits about as well as the current one (its chi-square within the
  // geometry's ambiguity allowance).
  virtual bool FitsAboutAsWell(const SwapFit& swap) const = 0;
  // Whether an alternative whose model fits `swap.worse` worse than the current one stands in
  // for `effect` (which the model would lose `effect_delta_chi2` without), among `alternatives`
  // candidates tried.
  virtual bool LooksAlike(size_t effect, const SwapFit& swap, double effect_delta_chi2,
                          size_t alternatives) const = 0;
  // The current model with `candidate` added beside its effects, fitted (FindPartners); false
  // when it cannot be fitted, or when the geometry does not offer it.
  virtual bool Beside(int candidate, BesideFit* fit) {
    (void)candidate;
    (void)fit;
    return false;
  }
};

struct SelectionOptions {
  double alpha = 0.005;  // the procedure's share for effects (Holm within a step)
  int max_effects = 6;
  int first_step = 1;  // the number of the first forward step
};

struct SelectionRecord {
  // Every candidate tested at every forward step.
  struct Score {
    int step = 0;
    int candidate = 0;
    double delta_chi2 = 0.0;
    double p_value = 1.0;
    bool significant = false;  // rejected by Holm at this step
  };
  // Every change of the model, in order.
  struct Change {
    bool added = true;  // false: dropped by backward elimination
    int step = 0;       // the forward step that added it, or the last one before the drop
    int candidate = 0;
    double delta_chi2 = 0.0;  // what it removed when added, or what it still removed when dropped
    double p_value = 1.0;     // at that moment
  };
  struct NotTested {
    int candidate = 0;
    std::string why;
  };
  std::vector<Score> scores;
  std::vector<Change> history;
  std::vector<NotTested> not_tested;
};

// Forward selection and backward elimination, alternating, over `candidates` (those not in the
// geometry's model). What a change implies beyond the refit (the tilt table re-decides its
// landmark tie) is the geometry's Add and Drop.
Status SelectEffects(DiscoveryGeometry* geometry, std::vector<int> candidates,
                     const SelectionOptions& options, SelectionRecord* record);

// Holm at `alpha` over the p-values of a model's effects: the least significant effect Holm
// does not find needed, or -1 when every one is.
int WeakestNotNeeded(const std::vector<double>& p_values, double alpha);

// The geometry's model with each of its effects replaced by each of `candidates` not in it,
// fitted once (FindLookAlikes and FindPartners judge the same fits); a swap that cannot be
// fitted is left out.
struct SwappedModel {
  size_t effect = 0;  // index into Effects()
  int alternative = 0;
  SwapFit fit;
};
std::vector<SwappedModel> FitSwaps(DiscoveryGeometry* geometry, const std::vector<int>& candidates);

// For each effect of the geometry's model, the candidates (of `candidates`, those not in the
// model) that could stand in for it: of `swaps`, those LooksAlike judges so.
// `effect_delta_chi2[e]`: what the model loses without effect e.
using LookAlike = SwappedModel;
std::vector<LookAlike> FindLookAlikes(const DiscoveryGeometry& geometry,
                                      const std::vector<int>& candidates,
                                      const std::vector<SwappedModel>& swaps,
                                      const std::vector<double>& effect_delta_chi2);

// Partners: candidates selection did not add that the data cannot tell from their absence where
// it matters. Two effects correlated in the design (each 3.5-4 sigma once the other is fitted)
// are the case; a partner is reported with the effect whose estimate it moves:
// - beside: added beside the model's effects, it gains p <= `alpha` (uncorrected for the
//   candidates tried: a doubt, not a finding) and moves an effect's estimate by at least
//   `shift_sigma` of the effect's sigma as fitted: that estimate carries the partner's signal if
//   the partner is there, and the data do not say whether it is; or, whatever it gains, the
//   design leaves it so much room that one of its sigmas beyond its estimate would move the
//   effect by `reach_sigma` or more (two effects each under 3 sigma once the other is fitted);
// - in another effect's place (`replaces`): of `swaps`, a model that fits about as well
//   (FitsAboutAsWell), where the partner explains what the effect it replaces explained at
//   p <= `alpha`, and an effect kept moves by `shift_sigma` or more: the data cannot say which of
//   the two look-alikes is there, and the kept effect's estimate depends on it (the tilt table's
//   nonorthogonality standing in for angle_offset's y part beside bias_drift_x).
struct Partner {
  size_t effect = 0;  // index into Effects(): the effect it moves
  int partner = 0;
  int replaces = -1;        // index into Effects(): the effect it stands in for; -1: beside them
  AlternativeFit fit;       // the model with it
  double delta_chi2 = 0.0;  // that model's chi-square minus the current one's
  // Beside: of its gain (-delta_chi2); replacing: of what it explains; chi-square(1).
  double p_value = 1.0;
  double shift_sigma = 0.0;  // |estimate with - without| / sigma without
  // Beside: the shift one sigma of the partner beyond its estimate would give (PartnerOptions).
  double reach_sigma = 0.0;
};
struct PartnerOptions {
  double alpha = 0.1;
  double shift_sigma = 2.0;
  // Beside: also a partner, whatever its gain, when the design leaves so much room that the
  // candidate one sigma beyond its estimate would move the effect by reach_sigma or more (the
  // shift at its estimate plus sqrt(r^2 - 1), r the effect's sigma beside it over its sigma as
  // fitted: the candidate's own sigma's worth of the effect's, exact for a linear model).
  double reach_sigma = 3.0;
};
std::vector<Partner> FindPartners(DiscoveryGeometry* geometry, const std::vector<int>& candidates,
                                  const std::vector<SwappedModel>& swaps,
                                  const std::vector<double>& effect_delta_chi2,
                                  const PartnerOptions& options);

// The verdict, in its precedence: structure the checks flag remains (unexplained, whatever was
// found), else an effect found has a look-alike (cannot tell apart), else effects or a noise
// model were found (missing), else explained.
Verdict DecideVerdict(bool structure_remains, bool look_alikes, bool found);

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_DISCOVERY_SELECTION_H_
