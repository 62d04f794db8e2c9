#include "estimation/statistics/parameter_determination.h"

#include <cmath>

#include "common/format.h"

namespace accelcal {

bool JudgeParameterDetermination(int p, const std::vector<std::string>& names,
                                 const Eigen::MatrixXd& covariance, double threshold,
                                 const std::string& threshold_words, double correlation,
                                 PoorlyDeterminedParameter* entry) {
  *entry = PoorlyDeterminedParameter();
  entry->index = p;
  entry->parameter = names[p];
  entry->sigma = std::sqrt(covariance(p, p));
  entry->threshold = threshold;
  entry->sigma_over_threshold = !(entry->sigma <= entry->threshold);
  for (int q = 0; q < static_cast<int>(names.size()); ++q) {
    if (q == p) continue;
    const double scale = std::sqrt(covariance(p, p) * covariance(q, q));
    const double rho = scale > 0.0 ? covariance(p, q) / scale : 0.0;
    if (std::fabs(rho) > correlation) entry->correlated_with.push_back({names[q], rho});
  }
  if (!entry->sigma_over_threshold && entry->correlated_with.empty()) return false;
  if (entry->sigma_over_threshold) {
    entry->reason = StringPrintf("sigma %.3g > %.3g (%s)", entry->sigma, entry->threshold,
                                 threshold_words.c_str());
  }
  if (!entry->correlated_with.empty()) {
    std::string with;
    for (const CorrelatedParameter& other : entry->correlated_with) {
      with += StringPrintf("%s%s (%+.4f)", with.empty() ? "" : ", ", other.parameter.c_str(),
                           other.correlation);
    }
    entry->reason += StringPrintf("%scorrelation beyond +-%g with %s",
                                  entry->reason.empty() ? "" : "; ", correlation, with.c_str());
  }
  return true;
}

std::string PoorlyDeterminedNames(const std::vector<PoorlyDeterminedParameter>& list) {
  std::string names;
  for (const PoorlyDeterminedParameter& entry : list)
    names += (names.empty() ? "" : ", ") + entry.parameter;
  return names;
}

}  // namespace accelcal
