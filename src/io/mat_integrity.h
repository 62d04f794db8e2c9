#ifndef ACCELCAL_IO_MAT_INTEGRITY_H_
#define ACCELCAL_IO_MAT_INTEGRITY_H_

// The structural walk of a MAT file before matio opens it (internal to io/mat_file.cc; see
// io/mat_file.h for why matio's own checks are not enough): the version dispatch, the walk of
// version 4 matrices and the version 7.3 superblock here, the walk of version 5 elements in
// io/mat5_integrity.h. The helpers below are shared by the walks of every version and by the
// version 7.3 reader (io/mat73_reader.h).

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "common/status.h"

namespace accelcal {
namespace mat_internal {

enum class MatVersion { kMat4, kMat5, kMat73 };

// Checks `path` before matio opens it: a regular file of sane size (CheckInputFile), then
// the walk of its version: version 5 top-level elements (CheckMat5Integrity, io/mat5_integrity.h),
// version 4 matrices (CheckMat4Integrity) or the version 7.3 superblock (CheckMat73Integrity).
Status CheckMatFile(const std::string& path, uint64_t* file_size, MatVersion* version);

// The largest rank a variable may declare (version 5 and 7.3).
constexpr uint32_t kMaxRank = 32;

// A 32-bit word of the file, byte-swapped when the writer's byte order is not ours.
inline uint32_t ReadUint32(const unsigned char* bytes, bool swap) {
  uint32_t value;
  std::memcpy(&value, bytes, 4);
  if (swap) value = __builtin_bswap32(value);
  return value;
}

// A MATLAB identifier, so that a damaged name cannot garble the one-line message.
bool IsIdentifier(const std::string& name);

// MATLAB and SciPy read the last of two variables of one name, matio the first: a file
// holding both gives different answers in different programs.
Status CheckUniqueNames(const std::vector<std::string>& names);

}  // namespace mat_internal
}  // namespace accelcal

#endif  // ACCELCAL_IO_MAT_INTEGRITY_H_
