#include "estimation/discovery/check.h"

#include "estimation/statistics/diagnostics.h"

namespace accelcal {

int FlagByHolm(double alpha, std::vector<ResidualCheck>* checks) {
  std::vector<double> p_values;
  for (const ResidualCheck& check : *checks) p_values.push_back(check.p_value);
  const std::vector<bool> rejected = HolmRejections(p_values, alpha);
  int flagged = 0;
  for (size_t i = 0; i < checks->size(); ++i) {
    (*checks)[i].flagged = rejected[i];
    flagged += rejected[i];
  }
  return flagged;
}

}  // namespace accelcal
