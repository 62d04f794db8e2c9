#include "io/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <vector>

#include "common/format.h"
#include "common/sha256.h"

namespace accelcal {
namespace {

std::string Bytes(uint64_t bytes) {
  if (bytes >= (1ull << 30)) return std::to_string(bytes >> 30) + " GiB";
  if (bytes >= (1ull << 20)) return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

const char* KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a pipe (FIFO)";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

FileIdentity IdentityOf(const struct stat& info) {
  FileIdentity identity;
  identity.device = static_cast<uint64_t>(info.st_dev);
  identity.inode = static_cast<uint64_t>(info.st_ino);
  identity.size = static_cast<uint64_t>(info.st_size);
  identity.modified_ns =
      static_cast<int64_t>(info.st_mtim.tv_sec) * 1000000000 + info.st_mtim.tv_nsec;
  identity.changed_ns =
      static_cast<int64_t>(info.st_ctim.tv_sec) * 1000000000 + info.st_ctim.tv_nsec;
  return identity;
}

struct InputReads {
  std::mutex mutex;
  bool on = false;
  std::map<std::string, InputRead> by_path;
  std::map<std::string, std::vector<InputFolderPart>> folders;
};

InputReads& TheInputReads() {
  static InputReads* reads = new InputReads;  // never destroyed: readers may run until exit
  return *reads;
}

// Closes a descriptor on every return.
struct FdCloser {
  int fd;
  ~FdCloser() { close(fd); }
};

constexpr char kCopyAdvice[] =
    "a logger may still be writing it; copy it once the recording has stopped and give the copy";

}  // namespace

ssize_t ReadSome(int fd, char* data, size_t size) {
  ssize_t count;
  do {
    count = read(fd, data, size);
  } while (count < 0 && errno == EINTR);
  return count;
}

bool FileIdentity::operator==(const FileIdentity& other) const {
  return device == other.device && inode == other.inode && size == other.size &&
         modified_ns == other.modified_ns && changed_ns == other.changed_ns;
}

Status IdentifyFile(const std::string& path, FileIdentity* identity) {
  struct stat info;
  if (stat(path.c_str(), &info) != 0) {
    return Status::Error(std::string("cannot read the file (") + std::strerror(errno) + ")");
  }
  *identity = IdentityOf(info);
  return Status::Ok();
}

Status IdentifyOpenFile(int fd, FileIdentity* identity) {
  struct stat info;
  if (fstat(fd, &info) != 0) {
    return Status::Error(std::string("cannot read the file (") + std::strerror(errno) + ")");
  }
  *identity = IdentityOf(info);
  return Status::Ok();
}

Status FileChangedWhileRead(const FileIdentity& before, const FileIdentity& after) {
  const std::string sizes = before.size == after.size
                                ? std::to_string(after.size) + " bytes, written to in between"
                                : std::to_string(before.size) + " bytes when opened, " +
                                      std::to_string(after.size) + " at the end";
  return Status::Error("the file changed while it was read (" + sizes + "): " + kCopyAdvice);
}

void StartRecordingInputReads() {
  InputReads& reads = TheInputReads();
  const std::lock_guard<std::mutex> lock(reads.mutex);
  reads.on = true;
  reads.by_path.clear();
  reads.folders.clear();
}

bool RecordingInputReads() {
  InputReads& reads = TheInputReads();
  const std::lock_guard<std::mutex> lock(reads.mutex);
  return reads.on;
}

Status RecordInputRead(const std::string& path, const InputRead& read) {
  InputReads& reads = TheInputReads();
  const std::lock_guard<std::mutex> lock(reads.mutex);
  if (!reads.on) return Status::Ok();
  const auto [found, added] = reads.by_path.emplace(path, read);
  if (added) return Status::Ok();
  const InputRead& first = found->second;
  if (first.sha256 != read.sha256 || first.bytes != read.bytes) {
    return Status::Error(StringPrintf(
        "the file changed between two readings of this run (%llu bytes, SHA-256 %.12s..., then "
        "%llu bytes, %.12s...): %s",
        static_cast<unsigned long long>(first.bytes), first.sha256.c_str(),
        static_cast<unsigned long long>(read.bytes), read.sha256.c_str(), kCopyAdvice));
  }
  found->second.identity = read.identity;
  return Status::Ok();
}

void RecordInputFolder(const std::string& folder, const std::vector<InputFolderPart>& parts) {
  InputReads& reads = TheInputReads();
  const std::lock_guard<std::mutex> lock(reads.mutex);
  if (reads.on) reads.folders[folder] = parts;
}

bool FindInputFolder(const std::string& folder, std::vector<InputFolderPart>* parts) {
  InputReads& reads = TheInputReads();
  const std::lock_guard<std::mutex> lock(reads.mutex);
  const auto found = reads.folders.find(folder);
  if (found == reads.folders.end()) return false;
  *parts = found->second;
  return true;
}

bool FindInputRead(const std::string& path, InputRead* read) {
  InputReads& reads = TheInputReads();
  const std::lock_guard<std::mutex> lock(reads.mutex);
  const auto found = reads.by_path.find(path);
  if (found == reads.by_path.end()) return false;
  *read = found->second;
  return true;
}

Status HashFile(const std::string& path, InputRead* read) {
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    return Status::Error(std::string("cannot open the file (") + std::strerror(errno) +
                         "); check the path and permissions");
  }
  const FdCloser closer{fd};
  FileIdentity before;
  ACCELCAL_RETURN_IF_ERROR(IdentifyOpenFile(fd, &before));
  Sha256 hash;
  std::vector<char> buffer(1 << 16);
  uint64_t total = 0;
  while (true) {
    const ssize_t count = ReadSome(fd, buffer.data(), buffer.size());
    if (count < 0) {
      return Status::Error(std::string("read error while computing its checksum (") +
                           std::strerror(errno) + ")");
    }
    if (count == 0) break;
    hash.Update(buffer.data(), static_cast<size_t>(count));
    total += static_cast<uint64_t>(count);
  }
  FileIdentity after;
  ACCELCAL_RETURN_IF_ERROR(IdentifyOpenFile(fd, &after));
  if (after != before || total != after.size) return FileChangedWhileRead(before, after);
  read->bytes = total;
  read->sha256 = hash.HexDigest();
  read->identity = after;
  return Status::Ok();
}

Status CheckInputFile(const std::string& path, uint64_t max_bytes, const std::string& what,
                      uint64_t* size) {
  struct stat info;
  if (stat(path.c_str(), &info) != 0) {
    if (errno == ENOENT) return Status::Error("no such file; check the path");
    return Status::Error(std::string("cannot read the file (") + std::strerror(errno) +
                         "); check the path and permissions");
  }
  if (!S_ISREG(info.st_mode)) {
    return Status::Error(std::string("is ") + KindOf(info.st_mode) + ", not " + what +
                         (S_ISFIFO(info.st_mode) ? "; save the stream to a file and name that"
                                                 : "; name the file itself"));
  }
  const uint64_t bytes = static_cast<uint64_t>(info.st_size);
  if (bytes > max_bytes) {
    return Status::Error("the file is " + Bytes(bytes) + ", more than the " + Bytes(max_bytes) +
                         " that " + what + " can sensibly be; is it the right file?");
  }
  *size = bytes;
  return Status::Ok();
}

namespace {

// CheckInputFile, then the whole file into `contents`; with `text`, its first 64 KiB must hold
// no NUL byte before anything larger is allocated.
Status ReadWhole(const std::string& path, uint64_t max_bytes, const std::string& what, bool text,
                 std::string* contents) {
  uint64_t size = 0;
  ACCELCAL_RETURN_IF_ERROR(CheckInputFile(path, max_bytes, what, &size));
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    return Status::Error(std::string("cannot open the file (") + std::strerror(errno) +
                         "); check the path and permissions");
  }
  const FdCloser closer{fd};
  auto read_some = [fd](char* data, size_t bytes) { return ReadSome(fd, data, bytes); };
  FileIdentity before;
  ACCELCAL_RETURN_IF_ERROR(IdentifyOpenFile(fd, &before));
  if (text) {
    char prefix[1 << 16];
    const ssize_t count = read_some(prefix, sizeof(prefix));
    const void* nul = count > 0 ? std::memchr(prefix, '\0', static_cast<size_t>(count)) : nullptr;
    if (nul != nullptr) {
      const long offset = static_cast<const char*>(nul) - prefix;
      return Status::Error("holds a NUL byte at byte " + std::to_string(offset) + ": it is not " +
                           what + " but a binary (or sparse, zero-filled) file");
    }
    if (lseek(fd, 0, SEEK_SET) != 0) {
      return Status::Error(std::string("cannot read the file (") + std::strerror(errno) + ")");
    }
  }
  try {
    contents->assign(size, '\0');
  } catch (const std::bad_alloc&) {
    contents->clear();
    return Status::Error("not enough memory to read the file's " + Bytes(size) +
                         "; free memory or raise the limit (ulimit -v)");
  }
  uint64_t done = 0;
  while (done < size) {
    const ssize_t count = read_some(&(*contents)[done], size - done);
    if (count <= 0) {
      const std::string why = count < 0 ? std::strerror(errno) : "it ended early";
      contents->clear();
      return Status::Error("cannot read the whole file (" + why + " after " + Bytes(done) + " of " +
                           Bytes(size) + "); was it being written?");
    }
    done += static_cast<uint64_t>(count);
  }
  // A file that grew or was written to while it was read is not the file that was checked.
  char extra;
  FileIdentity after;
  ACCELCAL_RETURN_IF_ERROR(IdentifyOpenFile(fd, &after));
  if (read_some(&extra, 1) != 0 || after != before) {
    contents->clear();
    return FileChangedWhileRead(before, after);
  }
  if (RecordingInputReads()) {
    const Status recorded = RecordInputRead(path, InputRead{size, Sha256Hex(*contents), after});
    if (!recorded.ok()) contents->clear();
    return recorded;
  }
  return Status::Ok();
}

}  // namespace

Status ReadInputFile(const std::string& path, uint64_t max_bytes, const std::string& what,
                     std::string* contents) {
  return ReadWhole(path, max_bytes, what, /*text=*/false, contents);
}

Status ReadInputText(const std::string& path, uint64_t max_bytes, const std::string& what,
                     std::string* contents) {
  return ReadWhole(path, max_bytes, what, /*text=*/true, contents);
}

}  // namespace accelcal
