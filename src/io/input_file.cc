#include "io/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>
#include <new>

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

}  // namespace

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
  // Closes the file on every return.
  const std::unique_ptr<const int, void (*)(const int*)> closer(&fd,
                                                                [](const int* f) { close(*f); });
  auto read_some = [fd](char* data, size_t bytes) {
    ssize_t count;
    do {
      count = read(fd, data, bytes);
    } while (count < 0 && errno == EINTR);
    return count;
  };
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
  // A file that grew while it was read is not the file that was checked.
  char extra;
  if (read_some(&extra, 1) != 0) {
    contents->clear();
    return Status::Error("the file changed while it was read; read it again when it is complete");
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
