#include "io/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
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

Status ReadInputFile(const std::string& path, uint64_t max_bytes, const std::string& what,
                     std::string* contents) {
  uint64_t size = 0;
  ACCELCAL_RETURN_IF_ERROR(CheckInputFile(path, max_bytes, what, &size));
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    return Status::Error(std::string("cannot open the file (") + std::strerror(errno) +
                         "); check the path and permissions");
  }
  try {
    contents->assign(size, '\0');
  } catch (const std::bad_alloc&) {
    close(fd);
    contents->clear();
    return Status::Error("not enough memory to read the file's " + Bytes(size) +
                         "; free memory or raise the limit (ulimit -v)");
  }
  uint64_t done = 0;
  while (done < size) {
    const ssize_t count = read(fd, &(*contents)[done], size - done);
    if (count < 0 && errno == EINTR) continue;
    if (count <= 0) {
      const std::string why = count < 0 ? std::strerror(errno) : "it ended early";
      close(fd);
      contents->clear();
      return Status::Error("cannot read the whole file (" + why + " after " + Bytes(done) + " of " +
                           Bytes(size) + "); was it being written?");
    }
    done += static_cast<uint64_t>(count);
  }
  // A file that grew while it was read is not the file that was checked.
  char extra;
  ssize_t more;
  do {
    more = read(fd, &extra, 1);
  } while (more < 0 && errno == EINTR);
  close(fd);
  if (more != 0) {
    contents->clear();
    return Status::Error("the file changed while it was read; read it again when it is complete");
  }
  return Status::Ok();
}

Status ReadInputText(const std::string& path, uint64_t max_bytes, const std::string& what,
                     std::string* contents) {
  uint64_t size = 0;
  ACCELCAL_RETURN_IF_ERROR(CheckInputFile(path, max_bytes, what, &size));
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    return Status::Error(std::string("cannot open the file (") + std::strerror(errno) +
                         "); check the path and permissions");
  }
  char prefix[1 << 16];
  ssize_t count;
  do {
    count = read(fd, prefix, sizeof(prefix));
  } while (count < 0 && errno == EINTR);
  close(fd);
  if (count > 0) {
    const void* nul = std::memchr(prefix, '\0', static_cast<size_t>(count));
    if (nul != nullptr) {
      const long offset = static_cast<const char*>(nul) - prefix;
      return Status::Error("holds a NUL byte at byte " + std::to_string(offset) + ": it is not " +
                           what + " but a binary (or sparse, zero-filled) file");
    }
  }
  return ReadInputFile(path, max_bytes, what, contents);
}

}  // namespace accelcal
