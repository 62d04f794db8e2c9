#ifndef ACCELCAL_IO_INPUT_FILE_H_
#define ACCELCAL_IO_INPUT_FILE_H_

// What every reader checks before it reads: that the path names a regular file (not a
// folder, a device such as /dev/zero, a FIFO or a socket, whose size says nothing about
// what a read would return) no larger than the reader's cap, and that reading it whole
// either succeeds or fails with a message; a memory failure is an error, never a
// truncated read. Messages carry no file name (callers add it with Status::WithContext).

#include <cstdint>
#include <string>

#include "common/status.h"

namespace accelcal {

// Caps on what a reader takes whole, with the reason each is generous.
// A .mat file is read into memory by matio; 4 GiB is 5e8 doubles, far beyond any test.
constexpr uint64_t kMaxMatFileBytes = 4ull << 30;
// A run or landmark CSV is held in memory as parsed numbers (3 per row).
constexpr uint64_t kMaxCsvFileBytes = 2ull << 30;
// datos.txt and scenario JSON are a few lines.
constexpr uint64_t kMaxConditionsFileBytes = 1ull << 20;

// Fails unless `path` is a regular file of at most `max_bytes` bytes; `size` gets its size.
// `what` names the kind of file in the message ("a MAT file", "a CSV file").
Status CheckInputFile(const std::string& path, uint64_t max_bytes, const std::string& what,
                      uint64_t* size);

// CheckInputFile, then reads the whole file into `contents`. A short read, an I/O error or
// a failed allocation is an error.
Status ReadInputFile(const std::string& path, uint64_t max_bytes, const std::string& what,
                     std::string* contents);

// ReadInputFile for a text file (CSV, datos.txt, JSON): before the whole file is read, its
// first 64 KiB must hold no NUL byte, so that a binary or sparse file (2 GB of zeros) is
// refused at once instead of being read whole and then parsed.
Status ReadInputText(const std::string& path, uint64_t max_bytes, const std::string& what,
                     std::string* contents);

}  // namespace accelcal

#endif  // ACCELCAL_IO_INPUT_FILE_H_
