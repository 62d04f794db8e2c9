#ifndef ACCELCAL_IO_MATIO_SUPPORT_H_
#define ACCELCAL_IO_MATIO_SUPPORT_H_

// What the MAT file reader (io/mat_file.cc) and its version 7.3 reader (io/mat73_reader.h)
// share of libmatio (internal to them): matio's log captured for our one-line errors, and a
// variable's header checked before its values are read.

#include <matio.h>

#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "io/mat_file.h"

namespace accelcal {
namespace mat_internal {

// matio reports problems through a global log function; by default it prints them on
// stderr. InstallMatioLogger keeps the last message instead (per thread, in
// LastMatioMessage()), so it can go into our one-line error.
void InstallMatioLogger();
std::string& LastMatioMessage();

// zlib, in MAT files and in HDF5 datasets alike, expands data by at most about 1032:1.
constexpr uint64_t kZlibExpansion = 1032;

// What ReadMatrix needs to know of a variable before it reads the values.
struct VariableInfo {
  std::string name;
  int class_type = MAT_C_EMPTY;
  bool is_complex = false;
  std::vector<uint64_t> dims;
  uint64_t element_bytes = 1;  // of the type the values are stored in
};

VariableInfo InfoOf(const matvar_t* var);

// Refuses what ReadMatrix cannot return: anything but a real, non-empty, two-dimensional
// double or single matrix, or one whose values could not fit in the file (`expansion`: what
// one byte of the file may become, 1 uncompressed, kZlibExpansion compressed).
Status CheckReadable(const VariableInfo& info, uint64_t file_size, uint64_t expansion);

// Copies the values matio read (double, or single widened to double).
void CopyValues(const matvar_t* var, const VariableInfo& info, MatMatrix* matrix);

}  // namespace mat_internal
}  // namespace accelcal

#endif  // ACCELCAL_IO_MATIO_SUPPORT_H_
