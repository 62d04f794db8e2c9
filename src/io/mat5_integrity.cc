#include "io/mat5_integrity.h"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "io/mat_integrity.h"

namespace accelcal {
namespace mat_internal {
namespace {

constexpr uint32_t kMiInt8 = 1;
constexpr uint32_t kMiInt32 = 5;
constexpr uint32_t kMiUint32 = 6;
constexpr uint32_t kMiMatrix = 14;
constexpr uint32_t kMiCompressed = 15;

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

}  // namespace

Status CheckMat5Integrity(const unsigned char* data, uint64_t size, bool swap) {
  constexpr size_t kHeaderBytes = 128;
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

}  // namespace mat_internal
}  // namespace accelcal
