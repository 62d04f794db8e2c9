#include "io/mat_file.h"

#include <fcntl.h>
#include <hdf5.h>
#include <matio.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>

#include "io/atomic_file.h"
#include "io/input_file.h"

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

uint64_t RoundUp8(uint64_t bytes) { return (bytes + 7) / 8 * 8; }

// The size of one value of a numeric data type (miINT8 ... miUINT64), 0 for any other
// type. MATLAB may store a double array in a smaller type (miUINT8 for small integers);
// the count of values, not their type, must match the dimensions.
uint64_t NumericTypeBytes(uint32_t type) {
  switch (type) {
    case 1:  // miINT8
    case 2:  // miUINT8
      return 1;
    case 3:  // miINT16
    case 4:  // miUINT16
      return 2;
    case 5:  // miINT32
    case 6:  // miUINT32
    case 7:  // miSINGLE
      return 4;
    case 9:   // miDOUBLE
    case 12:  // miINT64
    case 13:  // miUINT64
      return 8;
    default:
      return 0;
  }
}

const char* NumericTypeName(uint32_t type) {
  static const char* const kNames[] = {"",      "int8",   "uint8",  "int16", "uint16",
                                       "int32", "uint32", "single", "",      "double",
                                       "",      "",       "int64",  "uint64"};
  return type < sizeof(kNames) / sizeof(kNames[0]) ? kNames[type] : "";
}

// A MATLAB identifier, so that a damaged name cannot garble the one-line message.
bool IsIdentifier(const std::string& name) {
  return !name.empty() && std::isalpha(static_cast<unsigned char>(name[0])) &&
         std::all_of(name.begin(), name.end(), [](char c) {
           return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
         });
}

// Sequential access to the bytes of one element: a span of the mapped file, or a compressed
// element's zlib stream inflated through a fixed buffer, so that no element is ever held
// whole in memory (a 64 KB stream may inflate to 66 MB, a 4 MB one to 4 GB).
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  // Copies the next `count` bytes to `out`, or skips them when `out` is null. False when
  // the bytes run out first.
  virtual bool Read(uint64_t count, unsigned char* out) = 0;
};

class SpanSource final : public ByteSource {
 public:
  SpanSource(const unsigned char* data, uint64_t size) : at_(data), left_(size) {}
  bool Read(uint64_t count, unsigned char* out) override {
    if (count > left_) return false;
    if (out != nullptr) std::memcpy(out, at_, count);
    at_ += count;
    left_ -= count;
    return true;
  }

 private:
  const unsigned char* at_;
  uint64_t left_;
};

class InflateSource final : public ByteSource {
 public:
  // kInflating: more may come; kEnded: the stream ended (Z_STREAM_END); kCut: the compressed
  // bytes ran out before the stream's end; kCorrupt: zlib refused the data.
  enum class State { kInflating, kEnded, kCut, kCorrupt };

  InflateSource(const unsigned char* compressed, uint32_t size) {
    stream_.next_in = const_cast<unsigned char*>(compressed);
    stream_.avail_in = size;
    initialised_ = inflateInit(&stream_) == Z_OK;
    if (!initialised_) {
      state_ = State::kCorrupt;
      zlib_message_ = "zlib cannot be initialised";
    }
  }
  ~InflateSource() override {
    if (initialised_) inflateEnd(&stream_);
  }
  InflateSource(const InflateSource&) = delete;
  InflateSource& operator=(const InflateSource&) = delete;

  bool Read(uint64_t count, unsigned char* out) override {
    while (count > 0) {
      if (next_ == end_ && !Refill()) return false;
      const uint64_t take = std::min<uint64_t>(count, end_ - next_);
      if (out != nullptr) {
        std::memcpy(out, buffer_ + next_, take);
        out += take;
      }
      next_ += take;
      count -= take;
      delivered_ += take;
    }
    return true;
  }

  State state() const { return state_; }
  // The bytes Read has handed out (the whole inflated stream once Read has failed).
  uint64_t delivered() const { return delivered_; }
  // Compressed bytes after the end of the stream (kEnded only).
  uint64_t left_over() const { return stream_.avail_in; }
  const std::string& zlib_message() const { return zlib_message_; }

 private:
  bool Refill() {
    if (state_ != State::kInflating) return false;
    stream_.next_out = buffer_;
    stream_.avail_out = sizeof(buffer_);
    const int result = inflate(&stream_, Z_NO_FLUSH);
    next_ = 0;
    end_ = sizeof(buffer_) - stream_.avail_out;
    if (result == Z_STREAM_END) {
      state_ = State::kEnded;
    } else if (result == Z_BUF_ERROR) {
      state_ = State::kCut;  // no progress with a whole output buffer: the input ran out
    } else if (result != Z_OK) {
      state_ = State::kCorrupt;
      zlib_message_ = stream_.msg != nullptr ? stream_.msg : "error " + std::to_string(result);
    }
    return end_ > 0 || state_ == State::kInflating;
  }

  z_stream stream_{};
  bool initialised_ = false;
  State state_ = State::kInflating;
  std::string zlib_message_;
  unsigned char buffer_[64 * 1024];
  uint64_t next_ = 0;
  uint64_t end_ = 0;
  uint64_t delivered_ = 0;
};

// Checks a miMATRIX element whose `size` bytes (after its tag) `source` delivers, and
// consumes exactly them when it succeeds: the array flags, a dimensions subelement of a
// sane rank with no negative size, a name; for numeric classes, real (and imaginary) data
// holding exactly one value per element; for structs, objects and cells, their field names
// and nested elements, `depth` levels down. matio allocates what these subelements declare
// before reading them, so a corrupted rank or field-name length would otherwise ask for
// gigabytes or terabytes (found by tests/fuzz/mat_file_fuzzer), and it reads a data
// subelement shorter than the dimensions into the following bytes, or zeros, silently.
// `name` (may be null) receives the variable's name once it is read, when it is a MATLAB
// identifier. When `source` runs out, the message says only "ends early": the caller knows
// why (a compressed stream that is cut or short).
Status CheckMatrixElement(ByteSource* source, uint64_t size, bool swap, size_t offset, int depth,
                          std::string* name) {
  constexpr uint32_t kCellClass = 1;
  constexpr uint32_t kStructClass = 2;
  constexpr uint32_t kObjectClass = 3;
  constexpr uint32_t kSparseClass = 5;
  constexpr uint32_t kDoubleClass = 6;
  constexpr uint32_t kUint64Class = 15;
  constexpr uint32_t kComplexFlag = 0x800;
  constexpr int kMaxDepth = 16;
  constexpr uint32_t kMaxFieldNameBytes = 4096;
  constexpr uint32_t kMaxNameBytes = 4096;
  const std::string where = "the variable at byte " + std::to_string(offset);
  const std::string damaged = "; the file is damaged";
  const Status ran_out = Status::Error(where + " ends early" + damaged);
  uint64_t at = 0;  // bytes of the element consumed
  const auto read = [&](uint64_t count, unsigned char* out) {
    if (!source->Read(count, out)) return false;
    at += count;
    return true;
  };
  // Consumes the rest of the element unchecked.
  const auto finish = [&]() { return read(size - at, nullptr) ? Status::Ok() : ran_out; };
  // Reads the next subelement's tag into `tag` and its data into `data` (when not null and
  // at most `keep` bytes; otherwise skips them), then its padding.
  const auto next = [&](const char* what, Tag* tag, std::string* data, uint64_t keep) -> Status {
    if (size < at + 8) return Status::Error(where + " ends before its " + what + damaged);
    unsigned char raw[8];
    if (!read(8, raw)) return ran_out;
    *tag = ReadTag(raw, swap);
    if (data != nullptr) data->clear();
    if (tag->header_bytes == 4) {
      if (tag->bytes > 4) return Status::Error(where + " has a corrupt " + what + damaged);
      if (data != nullptr) data->assign(reinterpret_cast<const char*>(raw) + 4, tag->bytes);
      return Status::Ok();
    }
    if (size < at + tag->bytes) return Status::Error(where + " has a corrupt " + what + damaged);
    if (data != nullptr && tag->bytes <= keep) {
      data->resize(tag->bytes);
      if (!read(tag->bytes, reinterpret_cast<unsigned char*>(&(*data)[0]))) return ran_out;
    } else if (!read(tag->bytes, nullptr)) {
      return ran_out;
    }
    return read(std::min(RoundUp8(tag->bytes) - tag->bytes, size - at), nullptr) ? Status::Ok()
                                                                                 : ran_out;
  };

  if (size == 0) return Status::Ok();  // an empty element: matio skips it
  if (size < 16) return Status::Error(where + " is too short for a header");
  unsigned char header[16];
  if (!read(16, header)) return ran_out;
  const Tag flags = ReadTag(header, swap);
  if (flags.type != kMiUint32 || flags.bytes != 8 || flags.header_bytes != 8) {
    return Status::Error(where + " has corrupt array flags" + damaged);
  }
  const uint32_t flags_word = ReadUint32(header + 8, swap);
  const uint32_t class_type = flags_word & 0xff;
  if (size < at + 8) return Status::Error(where + " ends before its dimensions" + damaged);
  unsigned char raw[8];
  if (!read(8, raw)) return ran_out;
  const Tag dims = ReadTag(raw, swap);
  if (dims.type != kMiInt32 || dims.bytes % 4 != 0 || dims.bytes < 8 || dims.bytes > 4 * kMaxRank) {
    return Status::Error(where + " declares corrupt dimensions (" + std::to_string(dims.bytes) +
                         " bytes)" + damaged);
  }
  if (size < at + dims.bytes) return Status::Error(where + " ends inside its dimensions");
  unsigned char dims_data[4 * kMaxRank];
  if (!read(dims.bytes, dims_data) ||
      !read(std::min(RoundUp8(dims.bytes) - dims.bytes, size - at), nullptr)) {
    return ran_out;
  }
  uint64_t element_count = 1;  // saturates at 2^40, far beyond any file
  std::string shape;           // "20001x2"
  for (uint32_t k = 0; k < dims.bytes / 4; ++k) {
    const int32_t dimension = static_cast<int32_t>(ReadUint32(dims_data + 4 * k, swap));
    if (dimension < 0) return Status::Error(where + " declares a negative dimension" + damaged);
    element_count =
        std::min<uint64_t>(element_count * static_cast<uint64_t>(dimension), 1ull << 40);
    shape += (k == 0 ? "" : "x") + std::to_string(dimension);
  }
  Tag name_tag;
  std::string variable_name;
  ACCELCAL_RETURN_IF_ERROR(next("name", &name_tag, &variable_name, kMaxNameBytes));
  if (name_tag.type != kMiInt8) return Status::Error(where + " has a corrupt name" + damaged);
  if (!IsIdentifier(variable_name)) variable_name.clear();
  if (name != nullptr) *name = variable_name;
  const std::string variable = variable_name.empty() ? where : "variable '" + variable_name + "'";
  if (class_type == kSparseClass) return finish();  // matio sizes it by its nonzeros
  if (class_type != kCellClass && class_type != kStructClass && class_type != kObjectClass) {
    // Numeric and character data need at least a byte per value; function handles and
    // opaque classes, for whose values matio allocates a pointer each while listing the
    // variables, take far more (mat_file_fuzzer's fifth finding: a function handle
    // declaring 1.2e9 values made Mat_VarReadInfo ask for 9.7 GB).
    if (element_count > size - std::min(size, at)) {
      return Status::Error(
          (variable_name.empty() ? where : variable + " (at byte " + std::to_string(offset) + ")") +
          " declares " + std::to_string(element_count) + " values, more than its " +
          std::to_string(size) + " bytes can hold" + damaged);
    }
    // Characters may be UTF-8, of no fixed size; function handles and opaque classes hold
    // nested elements: their values are not counted.
    if (class_type < kDoubleClass || class_type > kUint64Class) return finish();
    // An empty array may end after its name.
    if (element_count == 0 && at == size) return Status::Ok();
    const int parts = (flags_word & kComplexFlag) != 0 ? 2 : 1;
    for (int part_index = 0; part_index < parts; ++part_index) {
      const std::string part = part_index == 0 ? "data" : "imaginary data";
      Tag data;
      ACCELCAL_RETURN_IF_ERROR(next(part.c_str(), &data, nullptr, 0));
      const uint64_t value_bytes = NumericTypeBytes(data.type);
      if (value_bytes == 0) {
        return Status::Error(variable + " has " + part + " of type " + std::to_string(data.type) +
                             ", not a number type" + damaged);
      }
      if (data.bytes % value_bytes != 0) {
        return Status::Error(variable + " declares " + shape + " values but its " + part +
                             " holds " + std::to_string(data.bytes) +
                             " bytes, not a whole number of " + NumericTypeName(data.type) +
                             " values" + damaged);
      }
      if (data.bytes / value_bytes != element_count) {
        return Status::Error(variable + " declares " + shape + " values but its " + part +
                             " holds " + std::to_string(data.bytes / value_bytes) + " (" +
                             std::to_string(data.bytes) + " bytes of " +
                             NumericTypeName(data.type) + ")" + damaged);
      }
    }
    return finish();
  }
  if (depth >= kMaxDepth) {
    return Status::Error(where + " nests cells or structs more than " + std::to_string(kMaxDepth) +
                         " deep" + damaged);
  }
  uint64_t nested_count = element_count;  // cells: one value each; structs: one per field
  if (class_type != kCellClass) {
    Tag tag;
    if (class_type == kObjectClass) ACCELCAL_RETURN_IF_ERROR(next("class name", &tag, nullptr, 0));
    std::string length;
    ACCELCAL_RETURN_IF_ERROR(next("field name length", &tag, &length, 4));
    if (tag.type != kMiInt32 || tag.bytes != 4 || length.size() != 4) {
      return Status::Error(where + " has a corrupt field name length" + damaged);
    }
    const uint32_t field_name_bytes =
        ReadUint32(reinterpret_cast<const unsigned char*>(length.data()), swap);
    ACCELCAL_RETURN_IF_ERROR(next("field names", &tag, nullptr, 0));
    if (field_name_bytes == 0 || field_name_bytes > kMaxFieldNameBytes ||
        tag.bytes % field_name_bytes != 0) {
      return Status::Error(where + " declares field names of " + std::to_string(field_name_bytes) +
                           " bytes" + damaged);
    }
    nested_count = std::min<uint64_t>(element_count * (tag.bytes / field_name_bytes), 1ull << 40);
  }
  // matio allocates a pointer per value before reading them; each value is an element of at
  // least 8 bytes, so the count is bounded by the bytes left.
  if (nested_count > (size - std::min(size, at)) / 8) {
    return Status::Error(where + " declares " + std::to_string(nested_count) +
                         " cells or fields, more than its " + std::to_string(size) +
                         " bytes can hold" + damaged);
  }
  // The fields' or cells' values: nested matrices.
  while (at + 8 <= size) {
    if (!read(8, raw)) return ran_out;
    const Tag nested = ReadTag(raw, swap);
    if (nested.type != kMiMatrix || nested.header_bytes != 8 || size < at + nested.bytes) {
      return Status::Error(where + " holds a corrupt nested element" + damaged);
    }
    ACCELCAL_RETURN_IF_ERROR(
        CheckMatrixElement(source, nested.bytes, swap, offset, depth + 1, nullptr));
    at += nested.bytes;
    if (!read(std::min(RoundUp8(nested.bytes) - nested.bytes, size - at), nullptr)) return ran_out;
  }
  return finish();
}

// Checks a compressed element (its `size` bytes after the tag, at byte `offset`): the zlib
// stream must inflate whole (Z_STREAM_END) to one miMATRIX element of exactly the length its
// tag declares, with no compressed bytes after the stream, and that element must pass
// CheckMatrixElement. MATLAB, SciPy and matio all write miMATRIX lengths that are multiples
// of 8 and nothing after the stream; zero padding to 8 bytes, inflated or compressed, is
// still accepted. matio inflates what it can and hands back a short variable as zeros,
// without an error.
Status CheckCompressedElement(const unsigned char* compressed, uint32_t size, bool swap,
                              size_t offset, std::string* name) {
  const std::string damaged = "; the file is damaged";
  InflateSource source(compressed, size);
  // Names the variable once its name is known.
  const auto label = [&]() {
    return name->empty()
               ? "the compressed variable at byte " + std::to_string(offset)
               : "variable '" + *name + "' (compressed, at byte " + std::to_string(offset) + ")";
  };
  // What is wrong with the stream itself, given that `declared` bytes were expected after
  // the 8-byte tag; OK when the stream is not (yet) at fault.
  const auto stream_problem = [&](uint64_t declared) -> Status {
    const uint64_t inflated = source.delivered() - std::min<uint64_t>(source.delivered(), 8);
    switch (source.state()) {
      case InflateSource::State::kCorrupt:
        return Status::Error(label() + " does not inflate (zlib: " + source.zlib_message() + ")" +
                             damaged);
      case InflateSource::State::kCut:
        if (inflated >= declared) {
          return Status::Error(label() + " is cut short: its zlib stream stops before its end" +
                               damaged);
        }
        return Status::Error(label() + " is cut short: its zlib stream stops after " +
                             std::to_string(inflated) + " of the " + std::to_string(declared) +
                             " bytes it declares" + damaged);
      case InflateSource::State::kEnded:
        if (inflated < declared) {
          return Status::Error(label() + " inflates to " + std::to_string(inflated) +
                               " bytes, fewer than the " + std::to_string(declared) +
                               " its header declares" + damaged);
        }
        return Status::Ok();
      case InflateSource::State::kInflating:
        return Status::Ok();
    }
    return Status::Ok();
  };
  unsigned char tag_bytes[8];
  if (!source.Read(8, tag_bytes)) {
    if (source.state() == InflateSource::State::kCorrupt) return stream_problem(0);
    return Status::Error(label() + " is not a matrix (its zlib stream " +
                         (source.state() == InflateSource::State::kCut ? "stops" : "ends") +
                         " after " + std::to_string(source.delivered()) + " bytes)" + damaged);
  }
  if (ReadUint32(tag_bytes, swap) != kMiMatrix) {
    return Status::Error(label() + " is not a matrix" + damaged);
  }
  // zlib expands by at most about 1032:1; a larger claim is corrupt.
  const uint64_t declared = ReadUint32(tag_bytes + 4, swap);
  if (declared > 1032ull * size + 64) {
    return Status::Error(label() + " declares " + std::to_string(declared) +
                         " bytes, more than its " + std::to_string(size) +
                         " compressed bytes can hold" + damaged);
  }
  const uint64_t padding = RoundUp8(declared) - declared;
  const Status element = CheckMatrixElement(&source, declared, swap, offset, 0, name);
  if (!element.ok()) {
    // A stream that ends early fails the element check somewhere; say why it ended. The
    // rest is inflated (no further than the declared length) to count it.
    source.Read(8 + declared + padding - std::min(source.delivered(), 8 + declared + padding),
                nullptr);
    ACCELCAL_RETURN_IF_ERROR(stream_problem(declared));
    return element;
  }
  // After the element: its padding, zeros, then the end of the stream.
  uint64_t extra = 0;
  unsigned char byte = 0;
  while (extra <= padding && source.Read(1, &byte)) {
    ++extra;
    if (byte != 0 || extra > padding) {
      return Status::Error(label() + " inflates to more than the " + std::to_string(declared) +
                           " bytes its header declares" + damaged);
    }
  }
  ACCELCAL_RETURN_IF_ERROR(stream_problem(declared));
  if (source.state() != InflateSource::State::kEnded) {
    return Status::Error(label() + " inflates to more than the " + std::to_string(declared) +
                         " bytes its header declares" + damaged);
  }
  // Nothing may follow the stream but zeros that align the element's end to 8 bytes (no
  // writer we know pads, but the padding would explain itself).
  const uint64_t left_over = source.left_over();
  const unsigned char* after = compressed + size - left_over;
  const bool aligning =
      (offset + 8 + size) % 8 == 0 && left_over < 8 &&
      std::all_of(after, after + left_over, [](unsigned char b) { return b == 0; });
  if (left_over > 0 && !aligning) {
    return Status::Error(label() + " has " + std::to_string(left_over) +
                         " bytes after the end of its zlib stream" + damaged);
  }
  return Status::Ok();
}

// MATLAB and SciPy read the last of two variables of one name, matio the first: a file
// holding both gives different answers in different programs.
Status CheckUniqueNames(const std::vector<std::string>& names) {
  std::map<std::string, int> count;
  for (const std::string& name : names) ++count[name];
  for (const std::string& name : names) {
    if (count[name] > 1) {
      return Status::Error("variable '" + name + "' appears " + std::to_string(count[name]) +
                           " times in the file; MATLAB would read the last, other readers the "
                           "first: save it again with one of each");
    }
  }
  return Status::Ok();
}

// Whether `type`, a version 4 matrix's MOPT field, is one matio reads: M (the number
// format) 0 or 1 (IEEE little or big endian; matio refuses VAX and Cray), O 0, P (the value
// type) 0-5, T (full, text, sparse) 0-2.
bool IsMat4Type(int64_t type) {
  return type >= 0 && type / 1000 <= 1 && type / 100 % 10 == 0 && type / 10 % 10 <= 5 &&
         type % 10 <= 2;
}

// matio reads a file that is neither version 5 nor 7.3 as version 4: matrices one after
// the other, each a 20-byte header (type, mrows, ncols, imagf, namlen as int32 in the
// writer's byte order), the name, then the real and imaginary values. It allocates namlen
// bytes, and later the values, before reading them, so a corrupted header would ask for
// gigabytes (mat_file_fuzzer's fourth finding: a namlen of 1.4e9 in a 638-byte file).
// Each matrix must fit in the bytes left, and no name may appear twice.
Status CheckMat4Integrity(const unsigned char* data, uint64_t size) {
  constexpr size_t kHeaderBytes = 20;
  constexpr uint64_t kValueBytes[] = {8, 4, 4, 2, 2, 1};  // by P: double ... uint8
  const std::string not_mat = "not a readable MAT file (";
  const std::string advice = "; save it from MATLAB/Octave with save -v7 or -v6";
  std::vector<std::string> names;
  uint64_t offset = 0;
  while (offset < size) {
    const std::string where = "the version 4 matrix at byte " + std::to_string(offset);
    const uint64_t remaining = size - offset;
    if (remaining < kHeaderBytes) {
      return Status::Error(offset == 0 ? not_mat + "too short for any header)" + advice
                                       : "the file is truncated: it ends inside the header of " +
                                             where + "; copy the file again");
    }
    // As matio reads it: the type in this machine's (little-endian) order, byte-swapped when
    // that is negative or above 4052; then M alone says the order of the other four fields,
    // however the type itself was written (mat_file_fuzzer's seventh finding: a type written
    // big endian with M = 0 made matio read a little-endian namlen of 1.09e9 and allocate it).
    int64_t type = static_cast<int32_t>(ReadUint32(data + offset, false));
    if (type < 0 || type > 4052) type = static_cast<int32_t>(ReadUint32(data + offset, true));
    const bool swap = type / 1000 == 1;
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
    // The name ends at its first NUL (namlen counts it).
    const char* name_at = reinterpret_cast<const char*>(data + offset + kHeaderBytes);
    const std::string name(name_at, strnlen(name_at, static_cast<size_t>(name_bytes)));
    if (IsIdentifier(name)) names.push_back(name);
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
  return CheckUniqueNames(names);
}

// A version 7.3 file is HDF5 behind a 512-byte MAT header (HDF5's "user block"). HDF5 finds
// its superblock at byte 0, 512, 1024, 2048 ...; the superblock records the end-of-file
// address (absolute, user block included) that HDF5 wrote. A file shorter than that is a
// truncated copy, which HDF5 refuses to open and matio then reports as a file without
// variables.
Status CheckMat73Integrity(const unsigned char* data, uint64_t size) {
  static const unsigned char kSignature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  const std::string truncated = "the file is truncated: ";
  const std::string again = "; copy it again";
  uint64_t at = 512;
  while (at + 8 <= size && std::memcmp(data + at, kSignature, 8) != 0) at *= 2;
  if (at + 8 > size) {
    if (at == 512) {
      return Status::Error(truncated + std::to_string(size) +
                           " bytes, less than a version 7.3 MAT file's header and HDF5 signature" +
                           again);
    }
    return Status::Error(
        "the file says it is a version 7.3 MAT file but holds no HDF5 data; the file is damaged");
  }
  // Superblock versions 0 and 1: the version, five more version/size bytes, the sizes of
  // offsets and lengths at 13 and 14, then (v0) 10 or (v1) 14 more bytes, then the base,
  // free-space, end-of-file and driver addresses. Versions 2 and 3: the sizes at 9 and 10,
  // a flags byte, then the base, extension and end-of-file addresses.
  const auto byte_at = [&](uint64_t k) -> int { return at + k < size ? data[at + k] : -1; };
  const int version = byte_at(8);
  int offset_bytes = -1;
  uint64_t eof_at = 0;
  if (version == 0 || version == 1) {
    offset_bytes = byte_at(13);
    eof_at = (version == 0 ? 24 : 28) + 2 * static_cast<uint64_t>(std::max(offset_bytes, 0));
  } else if (version == 2 || version == 3) {
    offset_bytes = byte_at(9);
    eof_at = 12 + 2 * static_cast<uint64_t>(std::max(offset_bytes, 0));
  } else {
    return Status::Error(version < 0 ? truncated + "it ends inside its HDF5 superblock" + again
                                     : "the HDF5 superblock at byte " + std::to_string(at) +
                                           " has an unknown version " + std::to_string(version) +
                                           "; the file is damaged");
  }
  if (offset_bytes < 0 || at + eof_at + 8 > size) {
    return Status::Error(truncated + "it ends inside its HDF5 superblock" + again);
  }
  if (offset_bytes != 8) return Status::Ok();  // other address sizes: left to HDF5
  uint64_t end_of_file = 0;
  for (int k = 7; k >= 0; --k) end_of_file = end_of_file << 8 | data[at + eof_at + k];
  if (end_of_file != ~0ull && end_of_file > size) {
    return Status::Error(truncated + "HDF5 wrote " + std::to_string(end_of_file) +
                         " bytes but the file has " + std::to_string(size) + again);
  }
  return Status::Ok();
}

// The file's bytes, mapped read-only: the walk reads only what it checks, so a large or
// sparse file costs address space, not memory. (Truncating the file while it is mapped
// would raise SIGBUS; readers do not expect their inputs to shrink under them.)
class MappedFile {
 public:
  MappedFile() = default;
  ~MappedFile() {
    if (data_ != nullptr) munmap(data_, size_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  // Maps `path`, which CheckInputFile found to be a regular file of `expected_size` bytes.
  Status Map(const std::string& path, uint64_t expected_size) {
    const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
      return Status::Error(std::string("cannot open the file (") + std::strerror(errno) +
                           "); check the path and permissions");
    }
    struct stat info;
    if (fstat(fd, &info) != 0 || !S_ISREG(info.st_mode) ||
        static_cast<uint64_t>(info.st_size) != expected_size) {
      close(fd);
      return Status::Error("the file changed while it was read; read it again when it is complete");
    }
    if (expected_size > 0) {
      void* mapped = mmap(nullptr, expected_size, PROT_READ, MAP_PRIVATE, fd, 0);
      if (mapped == MAP_FAILED) {
        const int error = errno;
        close(fd);
        return Status::Error(std::string("cannot map the file into memory (") +
                             std::strerror(error) + "); check the file and the limits (ulimit -v)");
      }
      data_ = static_cast<unsigned char*>(mapped);
      size_ = expected_size;
    }
    close(fd);
    return Status::Ok();
  }
  const unsigned char* data() const { return data_; }
  uint64_t size() const { return size_; }

 private:
  unsigned char* data_ = nullptr;
  uint64_t size_ = 0;
};

enum class MatVersion { kMat4, kMat5, kMat73 };

// Checks `path` before matio opens it: a regular file of sane size (CheckInputFile), then
// the walk of its version: version 5 top-level elements (none may run past the end of the
// file, each matrix passes CheckMatrixElement, each compressed one CheckCompressedElement,
// no name twice), version 4 matrices (CheckMat4Integrity) or the version 7.3 superblock
// (CheckMat73Integrity).
Status CheckMatFile(const std::string& path, uint64_t* file_size, MatVersion* version) {
  uint64_t size = 0;
  ACCELCAL_RETURN_IF_ERROR(CheckInputFile(path, kMaxMatFileBytes, "a MAT file", &size));
  MappedFile file;
  ACCELCAL_RETURN_IF_ERROR(file.Map(path, size));
  *file_size = size;
  *version = MatVersion::kMat4;
  if (size == 0) return Status::Error("the file is empty (0 bytes); it is not a MAT file");
  constexpr size_t kHeaderBytes = 128;
  const unsigned char* data = file.data();
  if (size < kHeaderBytes) {
    if (size < 6 || std::memcmp(data, "MATLAB", 6) != 0) return CheckMat4Integrity(data, size);
    return Status::Error("the file is truncated: " + std::to_string(size) +
                         " bytes, less than a MAT file's 128-byte header");
  }
  // matio recognises version 5 by the version and endian fields alone (bytes 124-127), not
  // by the "MATLAB" text, so neither does this walk (mat_file_fuzzer's second finding).
  // Like matio: version 5 (0x0100), 7.3 (0x0200, HDF5), else version 4.
  const bool swap = data[126] == 'M' && data[127] == 'I';
  if (!swap && !(data[126] == 'I' && data[127] == 'M')) return CheckMat4Integrity(data, size);
  uint16_t header_version;
  std::memcpy(&header_version, data + 124, 2);
  if (swap) header_version = __builtin_bswap16(header_version);
  if (header_version == 0x0200) {
    *version = MatVersion::kMat73;
    return CheckMat73Integrity(data, size);
  }
  if (header_version != 0x0100) return CheckMat4Integrity(data, size);
  *version = MatVersion::kMat5;
  std::vector<std::string> names;
  uint64_t offset = kHeaderBytes;
  while (offset < size) {
    const uint64_t remaining = size - offset;
    if (remaining < 8) {
      bool all_zero = true;
      for (uint64_t i = offset; i < size; ++i) all_zero = all_zero && data[i] == 0;
      if (all_zero) break;  // padding
      return Status::Error("the file is truncated: it ends inside a variable's header");
    }
    const uint32_t type = ReadUint32(data + offset, swap);
    uint64_t element_bytes = ReadUint32(data + offset + 4, swap);
    if (type == kMiMatrix) element_bytes = RoundUp8(element_bytes);
    if (element_bytes > remaining - 8) {
      return Status::Error("the file is truncated: a variable at byte " + std::to_string(offset) +
                           " declares " + std::to_string(element_bytes) + " bytes but only " +
                           std::to_string(remaining - 8) + " remain; copy the file again");
    }
    std::string name;
    if (type == kMiMatrix) {
      SpanSource source(data + offset + 8, element_bytes);
      ACCELCAL_RETURN_IF_ERROR(CheckMatrixElement(&source, element_bytes, swap, offset, 0, &name));
    } else if (type == kMiCompressed) {
      ACCELCAL_RETURN_IF_ERROR(CheckCompressedElement(
          data + offset + 8, static_cast<uint32_t>(element_bytes), swap, offset, &name));
    }
    if (!name.empty()) names.push_back(name);
    offset += 8 + element_bytes;
  }
  return CheckUniqueNames(names);
}

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

// ---- Version 7.3 (HDF5) files, read in a child process --------------------------------
//
// matio reads version 7.3 files through HDF5, and neither was written for hostile input:
// HDF5's advisories list many crashes and overflows on malformed files, and matio's v7.3
// reader reads attributes of any size into a single int ("FIXME: Check that dataspace is
// scalar", mat73.c). Neither library is built with our sanitizers, so a memory corruption
// would not even be seen, and no check of ours before the read can cover HDF5's whole
// format. A child process therefore reads the file: it opens it with HDF5, reads every
// variable ReadMatrix could return, and sends them through a pipe. If it crashes, hangs or
// runs out of memory, the parent reports one line; nothing of the child's state reaches the
// parent. (Version 7.3 files are rare in the course; one fork per file costs a millisecond.)

constexpr int kMat73ReaderTimeoutSeconds = 120;  // without a byte from the reader
constexpr uint64_t kMaxMessageBytes = 4096;
enum : uint64_t { kRecordVariable = 1, kRecordError = 2, kRecordEnd = 3 };
enum : uint64_t { kValuesNone = 0, kValuesRead = 1, kValuesFailed = 2 };

struct Mat73Variable {
  VariableInfo info;
  uint64_t values_kind = kValuesNone;
  std::string read_error;  // kValuesFailed: matio's message
  std::vector<double> values;
};

// HDF5 prints its error stack on stderr at every failed call; the reader keeps stderr for
// its one line. Once per process (the child's is a fresh one).
void SilenceHdf5() {
  static std::once_flag once;
  std::call_once(once, [] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); });
}

// The innermost (most specific) description on HDF5's error stack, on one line.
std::string Hdf5Error() {
  std::string message;
  H5Ewalk2(
      H5E_DEFAULT, H5E_WALK_DOWNWARD,
      [](unsigned, const H5E_error2_t* error, void* data) -> herr_t {
        if (error->desc != nullptr && error->desc[0] != '\0') {
          *static_cast<std::string*>(data) = error->desc;
        }
        return 0;
      },
      &message);
  for (char& c : message) {
    if (std::iscntrl(static_cast<unsigned char>(c))) c = ' ';
  }
  if (message.size() > 200) message = message.substr(0, 200) + "...";
  return message.empty() ? "no reason given" : message;
}

// H5Literate's callback: stops at the first object of the root group whose header HDF5
// cannot read (matio skips it without a word, and the variable seems absent); `data` gets
// the one-line problem.
herr_t FindUnreadableVariable(hid_t group, const char* name, const H5L_info_t*, void* data) {
  H5O_info_t info;
  if (H5Oget_info_by_name2(group, name, &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0) {
    *static_cast<std::string*>(data) =
        (IsIdentifier(name) ? "variable '" + std::string(name) + "'" : std::string("a variable")) +
        " cannot be read (HDF5: " + Hdf5Error() + "); the file is damaged";
    return 1;
  }
  return 0;
}

// H5Ovisit's callback, for every group and dataset of the file, nested ones (struct fields,
// cell elements) included: stops at the first that matio would misread; `data` gets the
// one-line problem. matio reads each of four attributes into a single number ("FIXME: Check
// that dataspace is scalar", mat73.c): a larger one overwrites its memory (an int32
// MATLAB_global of 4000 values crashes it). And HDF5 returns its fill value, zeros, for a
// dataset whose storage was never written or whose address was lost.
herr_t CheckHdf5Object(hid_t root, const char* path, const H5O_info_t* info, void* data) {
  if (info->type != H5O_TYPE_GROUP && info->type != H5O_TYPE_DATASET) return 0;
  std::string printable = path;
  for (char& c : printable) {
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  }
  if (printable.size() > 64) printable = printable.substr(0, 64) + "...";
  const std::string what =
      IsIdentifier(path) ? "variable '" + printable + "'" : "the HDF5 object '" + printable + "'";
  std::string* problem = static_cast<std::string*>(data);
  const hid_t object = H5Oopen(root, path, H5P_DEFAULT);
  if (object < 0) {
    *problem = what + " cannot be read (HDF5: " + Hdf5Error() + "); the file is damaged";
    return 1;
  }
  for (const char* attribute :
       {"MATLAB_global", "MATLAB_int_decode", "MATLAB_empty", "MATLAB_sparse"}) {
    if (H5Aexists(object, attribute) <= 0) continue;
    const hid_t opened = H5Aopen(object, attribute, H5P_DEFAULT);
    const hid_t space = opened >= 0 ? H5Aget_space(opened) : -1;
    const hssize_t values = space >= 0 ? H5Sget_simple_extent_npoints(space) : -1;
    if (space >= 0) H5Sclose(space);
    if (opened >= 0) H5Aclose(opened);
    if (values != 1) {
      *problem = what + " has a " + attribute + " attribute of " + std::to_string(values) +
                 " values where MATLAB writes one; the file is damaged";
      break;
    }
  }
  if (problem->empty() && info->type == H5O_TYPE_DATASET) {
    const hid_t space = H5Dget_space(object);
    const hssize_t points = space >= 0 ? H5Sget_simple_extent_npoints(space) : -1;
    H5D_space_status_t status = H5D_SPACE_STATUS_ERROR;
    const herr_t asked = H5Dget_space_status(object, &status);
    if (space >= 0) H5Sclose(space);
    if (points > 0 && (asked < 0 || status != H5D_SPACE_STATUS_ALLOCATED)) {
      *problem = what + " has no stored data (HDF5 would return zeros); the file is damaged";
    }
  }
  H5Oclose(object);
  return problem->empty() ? 0 : 1;
}

// In the child: opens the file with HDF5 itself before matio does, so that a failure is
// named in HDF5's words (matio takes a file HDF5 cannot open for a file without variables,
// and a variable it cannot read for an absent one), then checks every object as
// CheckHdf5Object does.
Status CheckHdf5File(const std::string& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) {
    return Status::Error("HDF5 cannot open the version 7.3 file (" + Hdf5Error() +
                         "); the file is damaged");
  }
  std::string problem;
  hsize_t index = 0;
  const herr_t listed =
      H5Literate(file, H5_INDEX_NAME, H5_ITER_NATIVE, &index, FindUnreadableVariable, &problem);
  if (listed < 0) {
    const std::string why = Hdf5Error();
    H5Fclose(file);
    return Status::Error("HDF5 cannot list the variables of the version 7.3 file (" + why +
                         "); the file is damaged");
  }
  if (!problem.empty()) {
    H5Fclose(file);
    return Status::Error(problem);
  }
  const herr_t visited =
      H5Ovisit2(file, H5_INDEX_NAME, H5_ITER_NATIVE, CheckHdf5Object, &problem, H5O_INFO_BASIC);
  const std::string why = visited < 0 ? Hdf5Error() : "";
  H5Fclose(file);
  if (!problem.empty()) return Status::Error(problem);
  if (visited < 0) {
    return Status::Error("HDF5 cannot read the objects of the version 7.3 file (" + why +
                         "); the file is damaged");
  }
  return Status::Ok();
}

class PipeWriter {
 public:
  explicit PipeWriter(int fd) : fd_(fd) {}
  void Bytes(const void* data, size_t count) {
    const char* at = static_cast<const char*>(data);
    while (ok_ && count > 0) {
      const ssize_t written = write(fd_, at, count);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) {
        ok_ = false;
        break;
      }
      at += written;
      count -= static_cast<size_t>(written);
    }
  }
  void Number(uint64_t value) { Bytes(&value, sizeof(value)); }
  void Text(const std::string& text) {
    Number(text.size());
    Bytes(text.data(), text.size());
  }
  bool ok() const { return ok_; }

 private:
  int fd_;
  bool ok_ = true;
};

class PipeReader {
 public:
  PipeReader(int fd, int timeout_seconds) : fd_(fd), timeout_ms_(timeout_seconds * 1000) {}
  // False at the end of the stream, on an error, or after the timeout without a byte.
  bool Bytes(void* out, size_t count) {
    char* at = static_cast<char*>(out);
    while (count > 0) {
      pollfd ready{fd_, POLLIN, 0};
      const int polled = poll(&ready, 1, timeout_ms_);
      if (polled < 0 && errno == EINTR) continue;
      if (polled == 0) timed_out_ = true;
      if (polled <= 0) return false;
      const ssize_t got = read(fd_, at, count);
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) return false;
      at += got;
      count -= static_cast<size_t>(got);
    }
    return true;
  }
  bool Number(uint64_t* value) { return Bytes(value, sizeof(*value)); }
  bool Text(std::string* text) {
    uint64_t size = 0;
    if (!Number(&size) || size > kMaxMessageBytes) return false;
    text->resize(size);
    return Bytes(&(*text)[0], size);
  }
  bool timed_out() const { return timed_out_; }

 private:
  int fd_;
  int timeout_ms_;
  bool timed_out_ = false;
};

// In the child: reads the file and sends every variable's info and, for those ReadMatrix
// can return, its values; or one error record.
void SendMat73Variables(const std::string& path, uint64_t file_size, PipeWriter* out) {
  InstallMatioLogger();
  SilenceHdf5();
  const auto fail = [&](const std::string& message) {
    out->Number(kRecordError);
    out->Text(message);
  };
  const Status hdf5 = CheckHdf5File(path);
  if (!hdf5.ok()) return fail(hdf5.message());
  last_matio_message.clear();
  mat_t* mat = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
  if (mat == nullptr) {
    return fail("not a readable MAT file" +
                (last_matio_message.empty() ? "" : " (" + last_matio_message + ")") +
                "; save it from MATLAB/Octave with save -v7 or -v6");
  }
  std::vector<VariableInfo> infos;
  size_t longest_name = 0;
  while (matvar_t* var = Mat_VarReadNextInfo(mat)) {
    if (var->name != nullptr) infos.push_back(InfoOf(var));
    if (var->name != nullptr) longest_name = std::max(longest_name, infos.back().name.size());
    Mat_VarFree(var);
  }
  if (longest_name > kMaxMessageBytes) {
    Mat_Close(mat);
    return fail("a variable's name is " + std::to_string(longest_name) +
                " bytes long (MATLAB allows 63); the file is damaged");
  }
  if (!last_matio_message.empty()) {
    Mat_Close(mat);
    return fail("cannot list the variables (" + last_matio_message + ")");
  }
  for (const VariableInfo& info : infos) {
    out->Number(kRecordVariable);
    out->Text(info.name);
    out->Number(static_cast<uint64_t>(info.class_type));
    out->Number(info.is_complex ? 1 : 0);
    out->Number(info.dims.size());
    for (uint64_t dimension : info.dims) out->Number(dimension);
    out->Number(info.element_bytes);
    if (!CheckReadable(info, file_size, kZlibExpansion).ok()) {
      out->Number(kValuesNone);
      continue;
    }
    last_matio_message.clear();
    matvar_t* var = Mat_VarRead(mat, info.name.c_str());
    if (var == nullptr || var->data == nullptr || !last_matio_message.empty()) {
      out->Number(kValuesFailed);
      out->Text(last_matio_message.substr(0, kMaxMessageBytes));
    } else {
      MatMatrix matrix;
      CopyValues(var, info, &matrix);
      out->Number(kValuesRead);
      out->Bytes(matrix.values.data(), matrix.values.size() * sizeof(double));
    }
    if (var != nullptr) Mat_VarFree(var);
  }
  Mat_Close(mat);
  out->Number(kRecordEnd);
}

// In the parent: what the child sent, checked as input (a number out of range ends it).
Status ReceiveMat73Variables(PipeReader* in, uint64_t file_size,
                             std::vector<Mat73Variable>* variables) {
  const Status broken = Status::Error(
      "HDF5 could not read the version 7.3 file (its reader stopped without an "
      "answer); the file is damaged: open it in MATLAB and save it again");
  variables->clear();
  while (true) {
    uint64_t kind = 0;
    if (!in->Number(&kind)) return broken;
    if (kind == kRecordEnd) return Status::Ok();
    if (kind == kRecordError) {
      std::string message;
      return in->Text(&message) ? Status::Error(message) : broken;
    }
    if (kind != kRecordVariable || variables->size() > file_size) return broken;
    Mat73Variable variable;
    VariableInfo& info = variable.info;
    uint64_t class_type = 0, is_complex = 0, rank = 0;
    if (!in->Text(&info.name) || !in->Number(&class_type) || !in->Number(&is_complex) ||
        !in->Number(&rank) || rank > kMaxRank) {
      return broken;
    }
    info.class_type = static_cast<int>(std::min<uint64_t>(class_type, 255));
    info.is_complex = is_complex != 0;
    info.dims.resize(rank);
    for (uint64_t& dimension : info.dims) {
      if (!in->Number(&dimension)) return broken;
    }
    if (!in->Number(&info.element_bytes) || !in->Number(&variable.values_kind)) return broken;
    if (variable.values_kind == kValuesFailed) {
      if (!in->Text(&variable.read_error)) return broken;
    } else if (variable.values_kind == kValuesRead) {
      if (!CheckReadable(info, file_size, kZlibExpansion).ok()) return broken;
      try {
        variable.values.resize(info.dims[0] * info.dims[1]);
      } catch (const std::bad_alloc&) {
        return Status::Error("not enough memory for variable '" + info.name + "' (" +
                             std::to_string(info.dims[0]) + "x" + std::to_string(info.dims[1]) +
                             "); free memory or raise the limit (ulimit -v)");
      }
      if (!in->Bytes(variable.values.data(), variable.values.size() * sizeof(double))) {
        return broken;
      }
    } else if (variable.values_kind != kValuesNone) {
      return broken;
    }
    variables->push_back(std::move(variable));
  }
}

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ACCELCAL_ADDRESS_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define ACCELCAL_ADDRESS_SANITIZER 1
#endif

// In the child: bounds its address space to what it has, plus twice the largest variable the
// file can hold (matio's copy and ours) and 1 GiB for HDF5, so that a damaged file asking
// HDF5 for absurd amounts fails an allocation in the child rather than draw the OOM killer.
// Not under AddressSanitizer, whose shadow memory reserves terabytes of address space.
void LimitReaderMemory(uint64_t file_size) {
#ifndef ACCELCAL_ADDRESS_SANITIZER
  unsigned long long pages = 0;
  FILE* statm = std::fopen("/proc/self/statm", "r");
  if (statm == nullptr) return;
  const bool parsed = std::fscanf(statm, "%llu", &pages) == 1;
  std::fclose(statm);
  if (!parsed) return;
  const uint64_t largest = std::min<uint64_t>(file_size, 1ull << 30) * kZlibExpansion;
  const uint64_t limit =
      pages * static_cast<uint64_t>(sysconf(_SC_PAGESIZE)) + (1ull << 30) + 2 * largest;
  rlimit current;
  if (getrlimit(RLIMIT_AS, &current) == 0 &&
      (current.rlim_cur == RLIM_INFINITY || current.rlim_cur > limit)) {
    current.rlim_cur = limit;
    setrlimit(RLIMIT_AS, &current);
  }
#else
  (void)file_size;
#endif
}

Status ReadMat73InChild(const std::string& path, uint64_t file_size,
                        std::vector<Mat73Variable>* variables) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    return Status::Error(std::string("cannot start a reader for the version 7.3 file (") +
                         std::strerror(errno) + "); free some processes or files and retry");
  }
  const pid_t child = fork();
  if (child < 0) {
    const int error = errno;
    close(fds[0]);
    close(fds[1]);
    return Status::Error(std::string("cannot start a reader for the version 7.3 file (") +
                         std::strerror(error) + "); free some processes or memory and retry");
  }
  if (child == 0) {
    // Default dispositions, not the parent's cleanup handlers; no blocked signals; no life
    // beyond the parent's. _exit: no atexit handlers, no flushing of the parent's buffers.
    close(fds[0]);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    for (int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) signal(signal_number, SIG_DFL);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    LimitReaderMemory(file_size);
    PipeWriter out(fds[1]);
    SendMat73Variables(path, file_size, &out);
    _exit(out.ok() ? 0 : 1);
  }
  close(fds[1]);
  PipeReader in(fds[0], kMat73ReaderTimeoutSeconds);
  const Status status = ReceiveMat73Variables(&in, file_size, variables);
  close(fds[0]);
  if (!status.ok()) kill(child, SIGKILL);  // it may be waiting to write, or hung
  int wait_status = 0;
  while (waitpid(child, &wait_status, 0) < 0 && errno == EINTR) {
  }
  if (in.timed_out()) {
    return Status::Error("HDF5 read nothing for " + std::to_string(kMat73ReaderTimeoutSeconds) +
                         " s; the file may be damaged: open it in MATLAB and save it again");
  }
  if (!status.ok() && WIFSIGNALED(wait_status) && WTERMSIG(wait_status) != SIGKILL) {
    return Status::Error("HDF5 could not read the version 7.3 file (its reader died of signal " +
                         std::to_string(WTERMSIG(wait_status)) + ", " +
                         strsignal(WTERMSIG(wait_status)) +
                         "); the file is damaged: open it in MATLAB and save it again");
  }
  return status;
}

Status VariableNotFound(const std::string& variable, const std::vector<std::string>& names) {
  std::string listing;
  for (const std::string& name : names) listing += (listing.empty() ? "" : ", ") + name;
  // Names come from the file: nothing unprintable may garble or break the line.
  for (char& c : listing) {
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  }
  return Status::Error("variable '" + variable + "' not found (the file has: " +
                       (listing.empty() ? "no variables" : listing) + ")");
}

}  // namespace

struct MatFileReader::Impl {
  mat_t* mat = nullptr;
  uint64_t file_size = 0;
  bool mat73 = false;
  std::vector<Mat73Variable> mat73_variables;  // what the version 7.3 reader sent
  ~Impl() {
    if (mat != nullptr) Mat_Close(mat);
  }
};

MatFileReader::MatFileReader() : impl_(new Impl) {}
MatFileReader::~MatFileReader() = default;

Status MatFileReader::Open(const std::string& path) {
  InstallMatioLogger();
  MatVersion version = MatVersion::kMat4;
  ACCELCAL_RETURN_IF_ERROR(CheckMatFile(path, &impl_->file_size, &version));
  if (version == MatVersion::kMat73) {
    impl_->mat73 = true;
    return ReadMat73InChild(path, impl_->file_size, &impl_->mat73_variables);
  }
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
  if (impl_->mat73) {
    for (const Mat73Variable& variable : impl_->mat73_variables) {
      names->push_back(variable.info.name);
    }
    return Status::Ok();
  }
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
  const std::string where = "variable '" + variable + "'";
  if (impl_->mat73) {
    for (const Mat73Variable& candidate : impl_->mat73_variables) {
      if (candidate.info.name != variable) continue;
      ACCELCAL_RETURN_IF_ERROR(CheckReadable(candidate.info, impl_->file_size, kZlibExpansion));
      if (candidate.values_kind != kValuesRead) {
        return Status::Error(
            "cannot read " + where +
            (candidate.read_error.empty() ? "" : " (" + candidate.read_error + ")"));
      }
      matrix->rows = static_cast<int>(candidate.info.dims[0]);
      matrix->cols = static_cast<int>(candidate.info.dims[1]);
      matrix->values = candidate.values;
      return Status::Ok();
    }
    std::vector<std::string> names;
    ListVariables(&names);
    return VariableNotFound(variable, names);
  }
  Mat_Rewind(impl_->mat);
  last_matio_message.clear();
  matvar_t* info = Mat_VarReadInfo(impl_->mat, variable.c_str());
  if (info == nullptr) {
    std::vector<std::string> names;
    ListVariables(&names);
    return VariableNotFound(variable, names);
  }
  const std::unique_ptr<matvar_t, void (*)(matvar_t*)> info_owner(info, Mat_VarFree);
  VariableInfo readable = InfoOf(info);
  readable.name = variable;
  ACCELCAL_RETURN_IF_ERROR(CheckReadable(
      readable, impl_->file_size, info->compression == MAT_COMPRESSION_NONE ? 1 : kZlibExpansion));
  Mat_Rewind(impl_->mat);
  matvar_t* var = Mat_VarRead(impl_->mat, variable.c_str());
  if (var == nullptr || var->data == nullptr || !last_matio_message.empty()) {
    if (var != nullptr) Mat_VarFree(var);
    return Status::Error("cannot read " + where +
                         (last_matio_message.empty() ? "" : " (" + last_matio_message + ")"));
  }
  const std::unique_ptr<matvar_t, void (*)(matvar_t*)> var_owner(var, Mat_VarFree);
  CopyValues(var, readable, matrix);
  return Status::Ok();
}

Status MatFileReader::ReadAllMatrices(uint64_t max_values, const std::string& oversize_advice,
                                      std::vector<std::pair<std::string, MatMatrix>>* matrices) {
  matrices->clear();
  auto check_size = [&](const VariableInfo& info) {
    uint64_t values = 1;
    for (const uint64_t dimension : info.dims) values *= std::min<uint64_t>(dimension, 1ull << 32);
    if (values <= max_values) return Status::Ok();
    std::string shape;
    for (const uint64_t dimension : info.dims)
      shape += (shape.empty() ? "" : "x") + std::to_string(dimension);
    return Status::Error("variable '" + info.name + "' is " + shape + "; " + oversize_advice);
  };
  if (impl_->mat73) {
    for (const Mat73Variable& candidate : impl_->mat73_variables) {
      ACCELCAL_RETURN_IF_ERROR(check_size(candidate.info));
      MatMatrix matrix;
      ACCELCAL_RETURN_IF_ERROR(ReadMatrix(candidate.info.name, &matrix));
      matrices->emplace_back(candidate.info.name, std::move(matrix));
    }
    return Status::Ok();
  }
  // First pass: headers only, so that nothing large is read.
  std::vector<VariableInfo> infos;
  Mat_Rewind(impl_->mat);
  last_matio_message.clear();
  while (matvar_t* info = Mat_VarReadNextInfo(impl_->mat)) {
    const std::unique_ptr<matvar_t, void (*)(matvar_t*)> owner(info, Mat_VarFree);
    infos.push_back(InfoOf(info));
    ACCELCAL_RETURN_IF_ERROR(
        CheckReadable(infos.back(), impl_->file_size,
                      info->compression == MAT_COMPRESSION_NONE ? 1 : kZlibExpansion));
    ACCELCAL_RETURN_IF_ERROR(check_size(infos.back()));
  }
  if (!last_matio_message.empty()) {
    return Status::Error("cannot list the variables (" + last_matio_message + ")");
  }
  // Second pass: the data, variable after variable.
  Mat_Rewind(impl_->mat);
  for (const VariableInfo& info : infos) {
    matvar_t* var = Mat_VarReadNext(impl_->mat);
    const std::unique_ptr<matvar_t, void (*)(matvar_t*)> owner(var, Mat_VarFree);
    if (var == nullptr || var->data == nullptr || !last_matio_message.empty() ||
        var->name == nullptr || info.name != var->name) {
      return Status::Error("cannot read variable '" + info.name + "'" +
                           (last_matio_message.empty() ? "" : " (" + last_matio_message + ")"));
    }
    MatMatrix matrix;
    CopyValues(var, info, &matrix);
    matrices->emplace_back(info.name, std::move(matrix));
  }
  Mat_Rewind(impl_->mat);
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
