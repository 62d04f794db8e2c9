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
  bool is_logical = false;
  std::vector<uint64_t> dims;
  uint64_t element_bytes = 1;       // of the type the values are stored in
  std::vector<std::string> fields;  // a struct's field names, at most kMaxListedFields
};

// A struct's fields named in a message: the first few are enough to show what it holds.
constexpr size_t kMaxListedFields = 16;

VariableInfo InfoOf(const matvar_t* var);

// MATLAB's name of the variable's class, as `whos` prints it: "double", "int16", "logical",
// "char", "struct", "cell", "sparse" ...
std::string MatlabClassName(const VariableInfo& info);

// The classes a read returns: double and single (ReadMatrix), or integers too
// (ReadNumericMatrix).
enum class MatClasses { kFloating, kNumeric };

// Refuses what a read of `classes` cannot return: anything but a real, non-empty,
// two-dimensional matrix of those classes, or one whose values could not fit in the file
// (`expansion`: what one byte of the file may become, 1 uncompressed, kZlibExpansion
// compressed).
Status CheckReadable(const VariableInfo& info, uint64_t file_size, uint64_t expansion,
                     MatClasses classes = MatClasses::kFloating);

// Copies the values matio read, widened to double: single, and the integer classes, each
// exactly; a 64-bit integer a double cannot hold exactly (beyond 2^53) is refused.
Status CopyValues(const matvar_t* var, const VariableInfo& info, MatMatrix* matrix);

}  // namespace mat_internal
}  // namespace accelcal

#endif  // ACCELCAL_IO_MATIO_SUPPORT_H_
