#include "io/mat_file.h"

#include <matio.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>

#include "io/atomic_file.h"

namespace accelcal {
namespace {

// matio reports problems through a global log function; by default it prints them on
// stderr. We keep the last message instead, so it can go into our one-line error.
thread_local std::string last_matio_message;

void CaptureMatioLog(int log_level, char* message) {
  if (log_level & (MATIO_LOG_LEVEL_ERROR | MATIO_LOG_LEVEL_CRITICAL)) {
    last_matio_message = message ? message : "";
  }
}

void InstallMatioLogger() {
  static std::once_flag once;
  std::call_once(once, [] { Mat_LogInitFunc("accelcal", CaptureMatioLog); });
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

uint32_t ReadUint32(const unsigned char* bytes, bool swap) {
  uint32_t value;
  std::memcpy(&value, bytes, 4);
  if (swap) value = __builtin_bswap32(value);
  return value;
}

constexpr uint32_t kMiInt8 = 1;
constexpr uint32_t kMiInt32 = 5;
constexpr uint32_t kMiUint32 = 6;
constexpr uint32_t kMiMatrix = 14;
constexpr uint32_t kMiCompressed = 15;
constexpr uint32_t kMaxRank = 32;

// One tag of a data element: the full form (type, bytes) or the small form that packs up
// to 4 bytes of data with the type and size into 8 bytes.
struct Tag {
  uint32_t type = 0;
  uint32_t bytes = 0;
  size_t header_bytes = 8;  // 4 for the small form
};

Tag ReadTag(const unsigned char* at, bool swap) {
  Tag tag;
  const uint32_t first = ReadUint32(at, swap);
  if ((first >> 16) != 0) {
    tag.type = first & 0xffff;
    tag.bytes = first >> 16;
    tag.header_bytes = 4;
  } else {
    tag.type = first;
    tag.bytes = ReadUint32(at + 4, swap);
  }
  return tag;
}

// Checks a miMATRIX element (`body`: the `size` bytes after its tag, of which `available`
// are at hand; less for a compressed one, whose inflated prefix is all there is): the array
// flags, a dimensions subelement of a sane rank with no negative size, a name that fits and,
// for structs, objects and cells, their field names and nested elements, `depth` levels
// down. matio allocates what these subelements declare before reading them, so a corrupted
// rank or field-name length would otherwise ask for gigabytes or terabytes (found by
// tests/fuzz/mat_file_fuzzer).
Status CheckMatrixElement(const unsigned char* body, size_t size, size_t available, bool swap,
                          size_t offset, int depth) {
  constexpr uint32_t kCellClass = 1;
  constexpr uint32_t kStructClass = 2;
  constexpr uint32_t kObjectClass = 3;
  constexpr uint32_t kSparseClass = 5;
  constexpr int kMaxDepth = 16;
  constexpr uint32_t kMaxFieldNameBytes = 4096;
  const std::string where = "the variable at byte " + std::to_string(offset);
  const std::string damaged = "; the file is damaged";
  if (size == 0) return Status::Ok();  // an empty element: matio skips it
  const size_t limit = std::min(size, available);
  if (limit < 16) {
    return limit < size ? Status::Ok() : Status::Error(where + " is too short for a header");
  }
  const Tag flags = ReadTag(body, swap);
  if (flags.type != kMiUint32 || flags.bytes != 8 || flags.header_bytes != 8) {
    return Status::Error(where + " has corrupt array flags" + damaged);
  }
  const uint32_t class_type = ReadUint32(body + 8, swap) & 0xff;
  size_t at = 16;
  // Reads the next subelement's tag into `tag` and moves `at` past its data, or fails.
  auto next = [&](const char* what, Tag* tag) -> Status {
    if (limit < at + 8) return Status::Error(where + " ends before its " + what + damaged);
    *tag = ReadTag(body + at, swap);
    const size_t data_at = at + tag->header_bytes;
    if (size < data_at + tag->bytes) {
      return Status::Error(where + " has a corrupt " + what + damaged);
    }
    at = tag->header_bytes == 4 ? at + 8 : data_at + (tag->bytes + 7) / 8 * 8;
    return Status::Ok();
  };
  if (limit < at + 8) return Status::Error(where + " ends before its dimensions" + damaged);
  const Tag dims = ReadTag(body + at, swap);
  if (dims.type != kMiInt32 || dims.bytes % 4 != 0 || dims.bytes < 8 || dims.bytes > 4 * kMaxRank) {
    return Status::Error(where + " declares corrupt dimensions (" + std::to_string(dims.bytes) +
                         " bytes)" + damaged);
  }
  const size_t dims_at = at + dims.header_bytes;
  if (limit < dims_at + dims.bytes) return Status::Error(where + " ends inside its dimensions");
  uint64_t element_count = 1;  // saturates at 2^40, far beyond any file
  for (uint32_t k = 0; k < dims.bytes / 4; ++k) {
    const int32_t dimension = static_cast<int32_t>(ReadUint32(body + dims_at + 4 * k, swap));
    if (dimension < 0) return Status::Error(where + " declares a negative dimension" + damaged);
    element_count =
        std::min<uint64_t>(element_count * static_cast<uint64_t>(dimension), 1ull << 40);
  }
  at = dims_at + (dims.bytes + 7) / 8 * 8;
  Tag name;
  const size_t name_at = at;
  ACCELCAL_RETURN_IF_ERROR(next("name", &name));
  if (name.type != kMiInt8) return Status::Error(where + " has a corrupt name" + damaged);
  // For messages: the name when it is at hand (`next` checked only that it lies within the
  // element) and a MATLAB identifier, so that a damaged one cannot garble the line.
  const size_t name_data_at = name_at + name.header_bytes;
  std::string variable_name;
  if (name_data_at + name.bytes <= limit) {
    variable_name.assign(reinterpret_cast<const char*>(body + name_data_at), name.bytes);
    const bool identifier =
        !variable_name.empty() && std::isalpha(static_cast<unsigned char>(variable_name[0])) &&
        std::all_of(variable_name.begin(), variable_name.end(),
                    [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
    if (!identifier) variable_name.clear();
  }
  if (class_type == kSparseClass) return Status::Ok();  // matio sizes it by its nonzeros
  if (class_type != kCellClass && class_type != kStructClass && class_type != kObjectClass) {
    // Numeric and character data need at least a byte per value; function handles and
    // opaque classes, for whose values matio allocates a pointer each while listing the
    // variables, take far more (mat_file_fuzzer's fifth finding: a function handle
    // declaring 1.2e9 values made Mat_VarReadInfo ask for 9.7 GB). ReadMatrix then checks
    // the variable it reads against its data type's size.
    if (element_count > size - std::min(size, at)) {
      const std::string variable =
          variable_name.empty()
              ? where
              : "variable '" + variable_name + "' (at byte " + std::to_string(offset) + ")";
      return Status::Error(variable + " declares " + std::to_string(element_count) +
                           " values, more than its " + std::to_string(size) + " bytes can hold" +
                           damaged);
    }
    return Status::Ok();
  }
  if (depth >= kMaxDepth) {
    return Status::Error(where + " nests cells or structs more than " + std::to_string(kMaxDepth) +
                         " deep" + damaged);
  }
  uint64_t nested_count = element_count;  // cells: one value each; structs: one per field
  if (class_type != kCellClass) {
    if (class_type == kObjectClass) {
      Tag class_name;
      ACCELCAL_RETURN_IF_ERROR(next("class name", &class_name));
    }
    const size_t length_at = at;
    Tag length;
    ACCELCAL_RETURN_IF_ERROR(next("field name length", &length));
    if (length.type != kMiInt32 || length.bytes != 4) {
      return Status::Error(where + " has a corrupt field name length" + damaged);
    }
    const uint32_t field_name_bytes = ReadUint32(body + length_at + length.header_bytes, swap);
    Tag names;
    ACCELCAL_RETURN_IF_ERROR(next("field names", &names));
    if (field_name_bytes == 0 || field_name_bytes > kMaxFieldNameBytes ||
        names.bytes % field_name_bytes != 0) {
      return Status::Error(where + " declares field names of " + std::to_string(field_name_bytes) +
                           " bytes" + damaged);
    }
    nested_count = std::min<uint64_t>(element_count * (names.bytes / field_name_bytes), 1ull << 40);
  }
  // matio allocates a pointer per value before reading them; each value is an element of at
  // least 8 bytes, so the count is bounded by the bytes left.
  if (nested_count > (size - std::min(size, at)) / 8) {
    return Status::Error(where + " declares " + std::to_string(nested_count) +
                         " cells or fields, more than its " + std::to_string(size) +
                         " bytes can hold" + damaged);
  }
  // The fields' or cells' values: nested matrices, checked as far as the bytes are at hand.
  while (at + 8 <= limit) {
    const Tag nested = ReadTag(body + at, swap);
    if (nested.type != kMiMatrix || nested.header_bytes != 8 || size < at + 8 + nested.bytes) {
      return Status::Error(where + " holds a corrupt nested element" + damaged);
    }
    ACCELCAL_RETURN_IF_ERROR(
        CheckMatrixElement(body + at + 8, nested.bytes, limit - (at + 8), swap, offset, depth + 1));
    at += 8 + (nested.bytes + 7) / 8 * 8;
  }
  return Status::Ok();
}

// The first bytes of a compressed element, inflated, so that its matrix header can be
// checked like an uncompressed one. Fails when the stream does not inflate.
Status InflatePrefix(const unsigned char* compressed, size_t size, std::string* prefix,
                     size_t offset) {
  prefix->assign(512, '\0');
  z_stream stream{};
  if (inflateInit(&stream) != Z_OK) return Status::Error("zlib cannot be initialised");
  stream.next_in = const_cast<unsigned char*>(compressed);
  stream.avail_in = static_cast<uInt>(size);
  stream.next_out = reinterpret_cast<unsigned char*>(&(*prefix)[0]);
  stream.avail_out = static_cast<uInt>(prefix->size());
  const int result = inflate(&stream, Z_SYNC_FLUSH);
  prefix->resize(prefix->size() - stream.avail_out);
  inflateEnd(&stream);
  if (result != Z_OK && result != Z_STREAM_END && result != Z_BUF_ERROR) {
    return Status::Error("the compressed variable at byte " + std::to_string(offset) +
                         " does not inflate (zlib: " + (stream.msg ? stream.msg : "error") +
                         "); the file is damaged");
  }
  return Status::Ok();
}

// Whether `type`, a version 4 matrix's MOPT field, is one matio reads: M (the number
// format) 0-4, O 0, P (the value type) 0-5, T (full, text, sparse) 0-2.
bool IsMat4Type(int64_t type) {
  return type >= 0 && type / 1000 <= 4 && type / 100 % 10 == 0 && type / 10 % 10 <= 5 &&
         type % 10 <= 2;
}

// matio reads a file that is neither version 5 nor 7.3 as version 4: matrices one after
// the other, each a 20-byte header (type, mrows, ncols, imagf, namlen as int32 in the
// writer's byte order), the name, then the real and imaginary values. It allocates namlen
// bytes, and later the values, before reading them, so a corrupted header would ask for
// gigabytes (mat_file_fuzzer's fourth finding: a namlen of 1.4e9 in a 638-byte file).
// Each matrix must fit in the bytes left.
Status CheckMat4Integrity(const unsigned char* data, size_t size) {
  constexpr size_t kHeaderBytes = 20;
  constexpr uint64_t kValueBytes[] = {8, 4, 4, 2, 2, 1};  // by P: double ... uint8
  const std::string not_mat = "not a readable MAT file (";
  const std::string advice = "; save it from MATLAB/Octave with save -v7 or -v6";
  size_t offset = 0;
  while (offset < size) {
    const std::string where = "the version 4 matrix at byte " + std::to_string(offset);
    const size_t remaining = size - offset;
    if (remaining < kHeaderBytes) {
      return Status::Error(offset == 0 ? not_mat + "too short for any header)" + advice
                                       : "the file is truncated: it ends inside the header of " +
                                             where + "; copy the file again");
    }
    bool swap = false;
    int64_t type = static_cast<int32_t>(ReadUint32(data + offset, false));
    if (!IsMat4Type(type)) {
      swap = true;
      type = static_cast<int32_t>(ReadUint32(data + offset, true));
    }
    if (!IsMat4Type(type)) {
      return Status::Error(
          offset == 0 ? not_mat + "neither a version 5/7 header nor a version 4 matrix)" + advice
                      : where + " has a corrupt type field; the file is damaged");
    }
    const auto field = [&](int index) {
      return static_cast<int64_t>(
          static_cast<int32_t>(ReadUint32(data + offset + 4 * index, swap)));
    };
    const int64_t rows = field(1);
    const int64_t cols = field(2);
    const int64_t imaginary = field(3);
    const int64_t name_bytes = field(4);
    // Neither dimension may exceed the file's bytes, even when the other is 0 (an empty
    // 0 x 1.1e9 matrix made matio ask for 1.9 GB: mat_file_fuzzer's sixth finding), and
    // imagf is a flag.
    if (rows < 0 || cols < 0 || name_bytes < 1 || static_cast<uint64_t>(rows) > size ||
        static_cast<uint64_t>(cols) > size || (imaginary != 0 && imaginary != 1)) {
      return Status::Error(where + " declares " + std::to_string(rows) + "x" +
                           std::to_string(cols) + " values, imagf " + std::to_string(imaginary) +
                           " and a " + std::to_string(name_bytes) + "-byte name in a " +
                           std::to_string(size) + "-byte file; the file is damaged");
    }
    uint64_t left = remaining - kHeaderBytes;
    if (static_cast<uint64_t>(name_bytes) > left) {
      return Status::Error("the file is truncated or damaged: " + where + " declares a " +
                           std::to_string(name_bytes) + "-byte name but only " +
                           std::to_string(left) + " bytes remain");
    }
    left -= name_bytes;
    // rows, cols < 2^31: the count fits; its bytes are compared without overflow.
    const uint64_t values = static_cast<uint64_t>(rows) * static_cast<uint64_t>(cols);
    const uint64_t value_bytes = kValueBytes[type / 10 % 10] * (imaginary != 0 ? 2 : 1);
    if (values > left / value_bytes) {
      return Status::Error("the file is truncated or damaged: " + where + " declares " +
                           std::to_string(rows) + "x" + std::to_string(cols) + " values but only " +
                           std::to_string(left) + " bytes remain");
    }
    offset += kHeaderBytes + name_bytes + values * value_bytes;
  }
  return Status::Ok();
}

// Walks the top-level data elements of a version 5 MAT file and fails when one of them
// declares more bytes than the file has left (a truncated copy) or has a corrupt matrix
// header (CheckMatrixElement). A version 4 file is walked by CheckMat4Integrity; version
// 7.3 (HDF5) is left to matio.
Status CheckMat5Integrity(const std::string& path, uint64_t* file_size) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Status::Error("cannot open the file; check the path and permissions");
  std::ostringstream buffer;
  buffer << file.rdbuf();
  const std::string bytes = buffer.str();
  *file_size = bytes.size();
  if (bytes.empty()) return Status::Error("the file is empty (0 bytes); it is not a MAT file");
  constexpr size_t kHeaderBytes = 128;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < kHeaderBytes) {
    if (bytes.compare(0, 6, "MATLAB") != 0) return CheckMat4Integrity(data, bytes.size());
    return Status::Error("the file is truncated: " + std::to_string(bytes.size()) +
                         " bytes, less than a MAT file's 128-byte header");
  }
  // matio recognises version 5 by the version and endian fields alone (bytes 124-127), not
  // by the "MATLAB" text, so neither does this walk (mat_file_fuzzer's second finding).
  // Like matio: version 5 (0x0100), 7.3 (0x0200, HDF5, left to matio), else version 4.
  const bool swap = data[126] == 'M' && data[127] == 'I';
  if (!swap && !(data[126] == 'I' && data[127] == 'M'))
    return CheckMat4Integrity(data, bytes.size());
  uint16_t version;
  std::memcpy(&version, data + 124, 2);
  if (swap) version = __builtin_bswap16(version);
  if (version == 0x0200) return Status::Ok();
  if (version != 0x0100) return CheckMat4Integrity(data, bytes.size());
  size_t offset = kHeaderBytes;
  while (offset < bytes.size()) {
    const size_t remaining = bytes.size() - offset;
    if (remaining < 8) {
      bool all_zero = true;
      for (size_t i = offset; i < bytes.size(); ++i) all_zero = all_zero && data[i] == 0;
      if (all_zero) break;  // padding
      return Status::Error("the file is truncated: it ends inside a variable's header");
    }
    const uint32_t type = ReadUint32(data + offset, swap);
    uint64_t element_bytes = ReadUint32(data + offset + 4, swap);
    if (type == kMiMatrix) element_bytes = (element_bytes + 7) / 8 * 8;
    if (element_bytes > remaining - 8) {
      return Status::Error("the file is truncated: a variable at byte " + std::to_string(offset) +
                           " declares " + std::to_string(element_bytes) + " bytes but only " +
                           std::to_string(remaining - 8) + " remain; copy the file again");
    }
    if (type == kMiMatrix) {
      ACCELCAL_RETURN_IF_ERROR(
          CheckMatrixElement(data + offset + 8, element_bytes, element_bytes, swap, offset, 0));
    } else if (type == kMiCompressed) {
      std::string prefix;
      ACCELCAL_RETURN_IF_ERROR(InflatePrefix(data + offset + 8, element_bytes, &prefix, offset));
      const auto* inflated = reinterpret_cast<const unsigned char*>(prefix.data());
      if (prefix.size() < 8 || ReadUint32(inflated, swap) != kMiMatrix) {
        return Status::Error("the compressed variable at byte " + std::to_string(offset) +
                             " is not a matrix; the file is damaged");
      }
      // zlib expands by at most about 1032:1; a larger claim is corrupt.
      const uint64_t declared = ReadUint32(inflated + 4, swap);
      if (declared > 1032 * element_bytes + 64) {
        return Status::Error("the compressed variable at byte " + std::to_string(offset) +
                             " declares " + std::to_string(declared) + " bytes, more than its " +
                             std::to_string(element_bytes) +
                             " compressed bytes can hold; the file is damaged");
      }
      // Only the inflated prefix is at hand: the element is checked as far as it reaches.
      ACCELCAL_RETURN_IF_ERROR(
          CheckMatrixElement(inflated + 8, declared, prefix.size() - 8, swap, offset, 0));
    }
    offset += 8 + element_bytes;
  }
  return Status::Ok();
}

}  // namespace

struct MatFileReader::Impl {
  mat_t* mat = nullptr;
  uint64_t file_size = 0;
  ~Impl() {
    if (mat != nullptr) Mat_Close(mat);
  }
};

MatFileReader::MatFileReader() : impl_(new Impl) {}
MatFileReader::~MatFileReader() = default;

Status MatFileReader::Open(const std::string& path) {
  InstallMatioLogger();
  ACCELCAL_RETURN_IF_ERROR(CheckMat5Integrity(path, &impl_->file_size));
  last_matio_message.clear();
  impl_->mat = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
  if (impl_->mat == nullptr) {
    return Status::Error("not a readable MAT file" +
                         (last_matio_message.empty() ? "" : " (" + last_matio_message + ")") +
                         "; save it from MATLAB/Octave with save -v7 or -v6");
  }
  return Status::Ok();
}

Status MatFileReader::ListVariables(std::vector<std::string>* names) {
  names->clear();
  Mat_Rewind(impl_->mat);
  last_matio_message.clear();
  while (matvar_t* info = Mat_VarReadNextInfo(impl_->mat)) {
    if (info->name != nullptr) names->push_back(info->name);
    Mat_VarFree(info);
  }
  Mat_Rewind(impl_->mat);
  if (!last_matio_message.empty()) {
    return Status::Error("cannot list the variables (" + last_matio_message + ")");
  }
  return Status::Ok();
}

Status MatFileReader::ReadMatrix(const std::string& variable, MatMatrix* matrix) {
  Mat_Rewind(impl_->mat);
  last_matio_message.clear();
  matvar_t* info = Mat_VarReadInfo(impl_->mat, variable.c_str());
  if (info == nullptr) {
    std::vector<std::string> names;
    ListVariables(&names);
    std::string listing;
    for (const std::string& name : names) listing += (listing.empty() ? "" : ", ") + name;
    return Status::Error("variable '" + variable + "' not found (the file has: " +
                         (listing.empty() ? "no variables" : listing) + ")");
  }
  const std::unique_ptr<matvar_t, void (*)(matvar_t*)> info_owner(info, Mat_VarFree);
  const std::string where = "variable '" + variable + "'";
  if (info->class_type != MAT_C_DOUBLE && info->class_type != MAT_C_SINGLE) {
    return Status::Error(where + " is " + ClassName(info->class_type) +
                         "; expected a real double matrix");
  }
  if (info->isComplex) return Status::Error(where + " is complex; expected a real matrix");
  if (info->rank != 2) {
    return Status::Error(where + " has " + std::to_string(info->rank) +
                         " dimensions; expected a 2-D matrix");
  }
  const uint64_t rows = info->dims[0];
  const uint64_t cols = info->dims[1];
  if (rows == 0 || cols == 0) {
    return Status::Error(where + " is empty (" + std::to_string(rows) + "x" + std::to_string(cols) +
                         ")");
  }
  // A corrupted header can claim billions of values in a few bytes; do not let matio
  // allocate them. Uncompressed data needs its bytes in the file; zlib cannot expand
  // data by more than about 1032:1.
  const uint64_t element_size = Mat_SizeOf(info->data_type) > 0 ? Mat_SizeOf(info->data_type) : 1;
  const uint64_t expansion = info->compression == MAT_COMPRESSION_NONE ? 1 : 1032;
  if (rows > (1ull << 31) || cols > (1ull << 31) ||
      rows * cols * element_size > impl_->file_size * expansion) {
    return Status::Error(where + " claims " + std::to_string(rows) + "x" + std::to_string(cols) +
                         " values, more than the " + std::to_string(impl_->file_size) +
                         "-byte file can hold");
  }
  Mat_Rewind(impl_->mat);
  matvar_t* var = Mat_VarRead(impl_->mat, variable.c_str());
  if (var == nullptr || var->data == nullptr || !last_matio_message.empty()) {
    if (var != nullptr) Mat_VarFree(var);
    return Status::Error("cannot read " + where +
                         (last_matio_message.empty() ? "" : " (" + last_matio_message + ")"));
  }
  const std::unique_ptr<matvar_t, void (*)(matvar_t*)> var_owner(var, Mat_VarFree);
  matrix->rows = static_cast<int>(rows);
  matrix->cols = static_cast<int>(cols);
  matrix->values.resize(rows * cols);
  if (var->class_type == MAT_C_DOUBLE) {
    std::memcpy(matrix->values.data(), var->data, rows * cols * sizeof(double));
  } else {
    const auto* single = static_cast<const float*>(var->data);
    for (size_t i = 0; i < rows * cols; ++i) matrix->values[i] = single[i];
  }
  return Status::Ok();
}

Status WriteMatFile(const std::string& path,
                    const std::vector<std::pair<std::string, MatMatrix>>& variables) {
  InstallMatioLogger();
  return WriteAtomicallyWith(path, [&](const std::string& temporary_path) {
    last_matio_message.clear();
    mat_t* mat = Mat_CreateVer(temporary_path.c_str(), "MATLAB 5.0 MAT-file, written by accelcal",
                               MAT_FT_MAT5);
    if (mat == nullptr) return Status::Error("cannot create " + path + " " + last_matio_message);
    Status status;
    for (const auto& [name, matrix] : variables) {
      size_t dims[2] = {static_cast<size_t>(matrix.rows), static_cast<size_t>(matrix.cols)};
      matvar_t* var =
          Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims,
                        const_cast<double*>(matrix.values.data()), MAT_F_DONT_COPY_DATA);
      if (var == nullptr || Mat_VarWrite(mat, var, MAT_COMPRESSION_NONE) != 0) {
        status = Status::Error("cannot write variable '" + name + "' to " + path);
      }
      if (var != nullptr) Mat_VarFree(var);
      if (!status.ok()) break;
    }
    Mat_Close(mat);
    return status;
  });
}

}  // namespace accelcal
