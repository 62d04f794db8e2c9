#ifndef ACCELCAL_IO_SAMPLE_SPOOL_H_
#define ACCELCAL_IO_SAMPLE_SPOOL_H_

// A triad log's time stamps and accelerometer outputs spooled to a temporary binary file as
// they are read (four doubles a sample, 32 bytes), and read back in ranges: what lets a
// computation pass over a log too long to hold several times without parsing its text again
// (allan, issue 36, item 2). The file is created in $TMPDIR (else /tmp) and unlinked at once,
// so it is gone when the spool is, or when the process ends however it ends; its pages are the
// kernel's cache, not the process's memory. Writes are buffered (1 MB), reads use pread.

#include <array>
#include <cstddef>
#include <vector>

#include "common/status.h"
#include "common/triad_sample_source.h"

namespace accelcal {

class SampleSpool : public TriadSampleSource {
 public:
  SampleSpool() = default;
  ~SampleSpool() override;
  SampleSpool(const SampleSpool&) = delete;
  SampleSpool& operator=(const SampleSpool&) = delete;

  // Creates the file; fails, saying where, when it cannot.
  Status Open();
  // The next sample (after Open, before Finish).
  Status Append(double t_s, const std::array<double, 3>& output);
  // Flushes the buffer; then Read.
  Status Finish();

  size_t size() const override { return size_; }
  Status Read(size_t first, size_t count, TriadLog* batch) const override;

 private:
  Status Flush();

  int fd_ = -1;
  size_t size_ = 0;
  std::vector<double> buffer_;
  mutable std::vector<double> read_buffer_;
};

}  // namespace accelcal

#endif  // ACCELCAL_IO_SAMPLE_SPOOL_H_
