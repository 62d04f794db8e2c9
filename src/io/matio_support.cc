#include "io/matio_support.h"

#include <matio.h>

#include <cstdint>
#include <cstring>
#include <mutex>
#include <type_traits>

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
  info.is_logical = var->isLogical != 0;
  for (int k = 0; k < var->rank && var->dims != nullptr; ++k) info.dims.push_back(var->dims[k]);
  info.element_bytes = Mat_SizeOf(var->data_type) > 0 ? Mat_SizeOf(var->data_type) : 1;
  if (var->class_type == MAT_C_STRUCT) {
    // Names matio read with the header (version 5's are checked by mat5_integrity).
    matvar_t* mutable_var = const_cast<matvar_t*>(var);  // matio's getter is not const
    const unsigned count = Mat_VarGetNumberOfFields(mutable_var);
    char* const* names = Mat_VarGetStructFieldnames(var);
    for (unsigned k = 0; names != nullptr && k < count && k < kMaxListedFields; ++k) {
      if (names[k] != nullptr) info.fields.emplace_back(names[k], strnlen(names[k], 64));
    }
  }
  return info;
}

std::string MatlabClassName(const VariableInfo& info) {
  if (info.is_logical) return "logical";
  switch (info.class_type) {
    case MAT_C_CELL:
      return "cell";
    case MAT_C_STRUCT:
      return "struct";
    case MAT_C_OBJECT:
      return "object";
    case MAT_C_CHAR:
      return "char";
    case MAT_C_SPARSE:
      return "sparse";
    case MAT_C_FUNCTION:
      return "function_handle";
    case MAT_C_OPAQUE:
      return "opaque";
    default: {
      const std::string name = ClassName(static_cast<matio_classes>(info.class_type));
      return name.find(' ') == std::string::npos ? name : "unknown class";
    }
  }
}

Status CheckReadable(const VariableInfo& info, uint64_t file_size, uint64_t expansion,
                     MatClasses classes) {
  const std::string where = "variable '" + info.name + "'";
  const bool integer = info.class_type >= MAT_C_INT8 && info.class_type <= MAT_C_UINT64;
  const bool floating = info.class_type == MAT_C_DOUBLE || info.class_type == MAT_C_SINGLE;
  if (classes == MatClasses::kNumeric && (info.is_logical || (!floating && !integer))) {
    return Status::Error(where + " is " +
                         (info.is_logical
                              ? std::string("logical")
                              : ClassName(static_cast<matio_classes>(info.class_type))) +
                         "; expected a real numeric matrix");
  }
  if (classes == MatClasses::kFloating && !floating) {
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

namespace {

template <typename T>
Status Widen(const void* data, std::vector<double>* values) {
  const T* typed = static_cast<const T*>(data);
  for (size_t i = 0; i < values->size(); ++i) (*values)[i] = static_cast<double>(typed[i]);
  return Status::Ok();
}

// A 64-bit integer class: every value must come back from its double unchanged. 2^63 and 2^64
// are doubles but no int64 or uint64, hence the bound before the cast back.
template <typename T>
Status WidenExactly(const void* data, const VariableInfo& info, std::vector<double>* values) {
  const T* typed = static_cast<const T*>(data);
  constexpr double kBeyond = std::is_signed<T>::value ? 9223372036854775808.0    // 2^63
                                                      : 18446744073709551616.0;  // 2^64
  for (size_t i = 0; i < values->size(); ++i) {
    const double widened = static_cast<double>(typed[i]);
    if (widened >= kBeyond || static_cast<T>(widened) != typed[i]) {
      return Status::Error(
          "variable '" + info.name + "' is " + MatlabClassName(info) + " and its value " +
          std::to_string(typed[i]) + " (element " + std::to_string(i + 1) +
          ") is beyond 2^53, where a double cannot hold every integer; subtract its first value "
          "in MATLAB (x = double(x - x(1))) and save it again");
    }
    (*values)[i] = widened;
  }
  return Status::Ok();
}

}  // namespace

Status CopyValues(const matvar_t* var, const VariableInfo& info, MatMatrix* matrix) {
  const size_t count = info.dims[0] * info.dims[1];
  matrix->rows = static_cast<int>(info.dims[0]);
  matrix->cols = static_cast<int>(info.dims[1]);
  matrix->values.resize(count);
  // matio converts the stored type (MATLAB stores an int16 variable whose values fit as uint8)
  // to the class's own; data_type says which it holds.
  switch (var->data_type) {
    case MAT_T_DOUBLE:
      std::memcpy(matrix->values.data(), var->data, count * sizeof(double));
      return Status::Ok();
    case MAT_T_SINGLE:
      return Widen<float>(var->data, &matrix->values);
    case MAT_T_INT8:
      return Widen<int8_t>(var->data, &matrix->values);
    case MAT_T_UINT8:
      return Widen<uint8_t>(var->data, &matrix->values);
    case MAT_T_INT16:
      return Widen<int16_t>(var->data, &matrix->values);
    case MAT_T_UINT16:
      return Widen<uint16_t>(var->data, &matrix->values);
    case MAT_T_INT32:
      return Widen<int32_t>(var->data, &matrix->values);
    case MAT_T_UINT32:
      return Widen<uint32_t>(var->data, &matrix->values);
    case MAT_T_INT64:
      return WidenExactly<int64_t>(var->data, info, &matrix->values);
    case MAT_T_UINT64:
      return WidenExactly<uint64_t>(var->data, info, &matrix->values);
    default:
      return Status::Error("cannot read variable '" + info.name + "' (its values are stored as " +
                           "matio type " + std::to_string(var->data_type) + ")");
  }
}

}  // namespace mat_internal
}  // namespace accelcal
