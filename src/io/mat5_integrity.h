#ifndef ACCELCAL_IO_MAT5_INTEGRITY_H_
#define ACCELCAL_IO_MAT5_INTEGRITY_H_

// The walk of a version 5 (and 7.0) MAT file's data elements, part of the structural check
// of io/mat_integrity.h: every element's tags, sizes and nesting against what it declares,
// each compressed element inflated whole and exactly to its declared length, without ever
// holding an element whole in memory.

#include <cstdint>

#include "common/status.h"

namespace accelcal {
namespace mat_internal {

// Checks the `size` bytes at `data`, a version 5 file whose 128-byte header says it was
// written in the other byte order when `swap`: its top-level elements (none may run past the
// end of the file, each matrix passes the element check, each compressed one inflates to
// exactly one such matrix), no name twice.
Status CheckMat5Integrity(const unsigned char* data, uint64_t size, bool swap);

}  // namespace mat_internal
}  // namespace accelcal

#endif  // ACCELCAL_IO_MAT5_INTEGRITY_H_
