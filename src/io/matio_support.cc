#include "io/matio_support.h"

#include <matio.h>

#include <cstring>
#include <mutex>

namespace accelcal {
namespace mat_internal {
namespace {

thread_local std::string last_matio_message;

void CaptureMatioLog(int log_level, char* message) {
  if (log_level & (MATIO_LOG_LEVEL_ERROR | MATIO_LOG_LEVEL_CRITICAL)) {
    last_matio_message = message ? message : "";
  }
}

const char* ClassName(matio_classes class_type) {
  switch (class_type) {
    case MAT_C_CELL:
      return "a cell array";
    case MAT_C_STRUCT:
      return "a struct";
    case MAT_C_OBJECT:
      return "an object";
    case MAT_C_CHAR:
      return "a char array";
    case MAT_C_SPARSE:
      return "a sparse matrix";
    case MAT_C_DOUBLE:
      return "double";
    case MAT_C_SINGLE:
      return "single";
    case MAT_C_INT8:
      return "int8";
    case MAT_C_UINT8:
      return "uint8";
    case MAT_C_INT16:
      return "int16";
    case MAT_C_UINT16:
      return "uint16";
    case MAT_C_INT32:
      return "int32";
    case MAT_C_UINT32:
      return "uint32";
    case MAT_C_INT64:
      return "int64";
    case MAT_C_UINT64:
      return "uint64";
    case MAT_C_FUNCTION:
      return "a function handle";
    default:
      return "of an unknown class";
  }
}

}  // namespace

void InstallMatioLogger() {
  static std::once_flag once;
  std::call_once(once, [] { Mat_LogInitFunc("accelcal", CaptureMatioLog); });
}

std::string& LastMatioMessage() { return last_matio_message; }

VariableInfo InfoOf(const matvar_t* var) {
  VariableInfo info;
  info.name = var->name != nullptr ? var->name : "";
  info.class_type = var->class_type;
  info.is_complex = var->isComplex != 0;
  for (int k = 0; k < var->rank && var->dims != nullptr; ++k) info.dims.push_back(var->dims[k]);
  info.element_bytes = Mat_SizeOf(var->data_type) > 0 ? Mat_SizeOf(var->data_type) : 1;
  return info;
}

// Refuses what ReadMatrix cannot return: anything but a real, non-empty, two-dimensional
// double or single matrix, or one whose values could not fit in the file (`expansion`: what
// one byte of the file may become, 1 uncompressed, kZlibExpansion compressed).
Status CheckReadable(const VariableInfo& info, uint64_t file_size, uint64_t expansion) {
  const std::string where = "variable '" + info.name + "'";
  if (info.class_type != MAT_C_DOUBLE && info.class_type != MAT_C_SINGLE) {
    return Status::Error(where + " is " + ClassName(static_cast<matio_classes>(info.class_type)) +
                         "; expected a real double matrix");
  }
  if (info.is_complex) return Status::Error(where + " is complex; expected a real matrix");
  if (info.dims.size() != 2) {
    return Status::Error(where + " has " + std::to_string(info.dims.size()) +
                         " dimensions; expected a 2-D matrix");
  }
  const uint64_t rows = info.dims[0];
  const uint64_t cols = info.dims[1];
  if (rows == 0 || cols == 0) {
    return Status::Error(where + " is empty (" + std::to_string(rows) + "x" + std::to_string(cols) +
                         ")");
  }
  // A corrupted header can claim billions of values in a few bytes; do not let matio
  // allocate them. Uncompressed data needs its bytes in the file.
  if (rows > (1ull << 31) || cols > (1ull << 31) ||
      rows * cols * info.element_bytes > file_size * expansion) {
    return Status::Error(where + " claims " + std::to_string(rows) + "x" + std::to_string(cols) +
                         " values, more than the " + std::to_string(file_size) +
                         "-byte file can hold");
  }
  return Status::Ok();
}

// Copies the values matio read (double, or single widened to double).
void CopyValues(const matvar_t* var, const VariableInfo& info, MatMatrix* matrix) {
  const size_t count = info.dims[0] * info.dims[1];
  matrix->rows = static_cast<int>(info.dims[0]);
  matrix->cols = static_cast<int>(info.dims[1]);
  matrix->values.resize(count);
  if (var->class_type == MAT_C_DOUBLE) {
    std::memcpy(matrix->values.data(), var->data, count * sizeof(double));
  } else {
    const auto* single = static_cast<const float*>(var->data);
    for (size_t i = 0; i < count; ++i) matrix->values[i] = single[i];
  }
}

}  // namespace mat_internal
}  // namespace accelcal
