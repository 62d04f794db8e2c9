#include "common/progress.h"

namespace accelcal {

void ProgressCounter::Advance() {
  if (!report_) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  report_(++done_, total_);
}

ProgressFn ProgressPart(const ProgressFn& whole, int64_t offset, int64_t total) {
  if (!whole) return ProgressFn();
  return [whole, offset, total](int64_t done, int64_t) { whole(offset + done, total); };
}

}  // namespace accelcal
