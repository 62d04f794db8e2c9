#ifndef ACCELCAL_COMMON_PROGRESS_H_
#define ACCELCAL_COMMON_PROGRESS_H_

// How a long computation says how far it has got without printing anything itself: the
// studies count finished trials into a ProgressFn, and the binaries decide whether and how
// to show it (reporting/progress_printer.h writes the lines on stderr). A study's results
// never depend on it: the counts are only passed on, never read back.

#include <cstdint>
#include <functional>
#include <mutex>

namespace accelcal {

// `done` of `total` work units (trials) are finished. Called one call at a time, with
// `done` increasing, from whichever thread finished the unit. An empty function reports
// nothing.
using ProgressFn = std::function<void(int64_t done, int64_t total)>;

// Counts units finished on several threads and passes each count on. The callback runs
// under a mutex so that it sees the counts one at a time and in order, and need not be
// thread-safe itself; it is called once per unit, so it must be cheap (the printer
// throttles by the clock).
class ProgressCounter {
 public:
  ProgressCounter(ProgressFn report, int64_t total) : report_(std::move(report)), total_(total) {}
  ProgressCounter(const ProgressCounter&) = delete;
  ProgressCounter& operator=(const ProgressCounter&) = delete;

  // One more unit finished. Safe to call from any thread.
  void Advance();

 private:
  std::mutex mutex_;
  const ProgressFn report_;
  const int64_t total_;
  int64_t done_ = 0;
};

// One part of a larger job, so that a run made of several studies reports one count and
// one time left: the part's units are units [offset, offset + its total) of `total`, and
// its report (d, part_total) reaches `whole` as (offset + d, total). Empty when `whole` is.
ProgressFn ProgressPart(const ProgressFn& whole, int64_t offset, int64_t total);

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_PROGRESS_H_
