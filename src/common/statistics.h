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

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_STATISTICS_H_
