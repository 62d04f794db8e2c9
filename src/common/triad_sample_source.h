#ifndef ACCELCAL_COMMON_TRIAD_SAMPLE_SOURCE_H_
#define ACCELCAL_COMMON_TRIAD_SAMPLE_SOURCE_H_

// A triad log's samples read back in ranges, whether held in memory (TriadLog) or spooled to a
// file (io/sample_spool.h) for a log too long to hold (issue 36, item 2): what a computation
// that passes over a log a bounded number of times (the streamed noise-floor detector, allan)
// reads from. Only time stamps and accelerometer outputs.

#include <algorithm>
#include <array>
#include <cstddef>

#include "common/status.h"
#include "common/triad_log.h"

namespace accelcal {

class TriadSampleSource {
 public:
  virtual ~TriadSampleSource() = default;
  virtual size_t size() const = 0;
  // Samples [first, first + count) (within size()) into batch->timestamp_s and batch->output,
  // replacing what they held.
  virtual Status Read(size_t first, size_t count, TriadLog* batch) const = 0;
};

// A log in memory as a source (it must outlive the source).
class TriadLogSamples : public TriadSampleSource {
 public:
  explicit TriadLogSamples(const TriadLog& log) : log_(log) {}
  size_t size() const override { return log_.size(); }
  Status Read(size_t first, size_t count, TriadLog* batch) const override {
    batch->timestamp_s.assign(log_.timestamp_s.begin() + first,
                              log_.timestamp_s.begin() + first + count);
    batch->output.assign(log_.output.begin() + first, log_.output.begin() + first + count);
    return Status::Ok();
  }

 private:
  const TriadLog& log_;
};

// Calls visit(i, t_s, output) for the samples i = first .. last (inclusive) in order, read in
// batches of `batch_samples` (a template, so that a pass's per-sample work is inlined).
template <typename Visit>
Status ForEachSample(const TriadSampleSource& source, size_t first, size_t last, Visit&& visit,
                     size_t batch_samples = size_t{1} << 16) {
  TriadLog batch;
  for (size_t begin = first; begin <= last && begin < source.size(); begin += batch_samples) {
    const size_t count = std::min(batch_samples, last + 1 - begin);
    ACCELCAL_RETURN_IF_ERROR(source.Read(begin, count, &batch));
    for (size_t j = 0; j < count; ++j) visit(begin + j, batch.timestamp_s[j], batch.output[j]);
  }
  return Status::Ok();
}

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_TRIAD_SAMPLE_SOURCE_H_
