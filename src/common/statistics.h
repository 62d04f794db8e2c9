#ifndef ACCELCAL_COMMON_STATISTICS_H_
#define ACCELCAL_COMMON_STATISTICS_H_

// Order statistics shared across layers (io's time checks, models' unit checks, estimation).

#include <algorithm>
#include <vector>

namespace accelcal {

// The element of rank n/2 of `values` (0-based): the median for odd n, the upper of the two
// middle values for even n. By a partial sort of the copy, O(n); `values` must not be empty.
inline double UpperMedian(std::vector<double> values) {
  const auto middle = values.begin() + values.size() / 2;
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// The element of rank round(q (n - 1)) in increasing order, q in [0, 1]; `values` (not empty) is
// reordered. O(n).
inline double RankQuantile(std::vector<double>* values, double q) {
  const size_t rank = static_cast<size_t>(q * (values->size() - 1) + 0.5);
  std::nth_element(values->begin(), values->begin() + rank, values->end());
  return (*values)[rank];
}

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_STATISTICS_H_
