#ifndef ACCELCAL_IO_MAT73_READER_H_
#define ACCELCAL_IO_MAT73_READER_H_

// The reader of version 7.3 (HDF5) MAT files, internal to io/mat_file.cc, which runs it in a
// child process: HDF5 and matio on a damaged file may crash, hang or ask for all memory.

#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "io/matio_support.h"

namespace accelcal {
namespace mat_internal {

// Whether the child sent a variable's values: none (MatFileReader::ReadNumericMatrix would
// refuse it), read, failed with matio's message, or refused (a 64-bit integer a double cannot
// hold) with our one line.
enum : uint64_t { kValuesNone = 0, kValuesRead = 1, kValuesFailed = 2, kValuesRefused = 3 };

struct Mat73Variable {
  VariableInfo info;
  uint64_t values_kind = kValuesNone;
  std::string read_error;  // kValuesFailed: matio's message; kValuesRefused: the whole line
  std::vector<double> values;
};

// Reads every variable of the version 7.3 file `path` (of `file_size` bytes) in a child
// process: each variable's header, and the values of those ReadNumericMatrix can return. A child
// that crashes, hangs or runs out of memory is one line of Status; nothing of its state
// reaches the caller.
Status ReadMat73InChild(const std::string& path, uint64_t file_size,
                        std::vector<Mat73Variable>* variables);

}  // namespace mat_internal
}  // namespace accelcal

#endif  // ACCELCAL_IO_MAT73_READER_H_
