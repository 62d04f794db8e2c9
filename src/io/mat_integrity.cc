#include "io/mat_integrity.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <map>

#include "io/input_file.h"
#include "io/mat5_integrity.h"

namespace accelcal {
namespace mat_internal {

bool IsIdentifier(const std::string& name) {
  return !name.empty() && std::isalpha(static_cast<unsigned char>(name[0])) &&
         std::all_of(name.begin(), name.end(), [](char c) {
           return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
         });
}

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

namespace {

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

}  // namespace

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
  return CheckMat5Integrity(data, size, swap);
}

}  // namespace mat_internal
}  // namespace accelcal
