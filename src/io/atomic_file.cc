#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

namespace accelcal {
namespace {

std::string ErrnoText() { return std::strerror(errno); }

// Creates an empty temporary file beside `path`; returns its name.
Status MakeTemporarySibling(const std::string& path, std::string* temporary_path) {
  std::vector<char> name(path.begin(), path.end());
  const std::string suffix = ".tmp.XXXXXX";
  name.insert(name.end(), suffix.begin(), suffix.end());
  name.push_back('\0');
  const int fd = mkstemp(name.data());
  if (fd < 0) {
    return Status::Error("cannot create a file beside " + path + " (" + ErrnoText() +
                         "); check that the directory exists and is writable");
  }
  close(fd);
  *temporary_path = name.data();
  return Status::Ok();
}

}  // namespace

Status WriteAtomicallyWith(const std::string& path,
                           const std::function<Status(const std::string&)>& write) {
  std::string temporary_path;
  ACCELCAL_RETURN_IF_ERROR(MakeTemporarySibling(path, &temporary_path));
  Status status = write(temporary_path);
  if (status.ok()) {
    // mkstemp creates 0600; outputs are ordinary files a user's other tools can read.
    const mode_t mask = umask(0);
    umask(mask);
    chmod(temporary_path.c_str(), 0666 & ~mask);
    if (std::rename(temporary_path.c_str(), path.c_str()) != 0) {
      status = Status::Error("cannot rename " + temporary_path + " to " + path + " (" +
                             ErrnoText() + ")");
    }
  }
  if (!status.ok()) std::remove(temporary_path.c_str());
  return status;
}

Status WriteFileAtomically(const std::string& path, const std::string& contents) {
  return WriteAtomicallyWith(path, [&](const std::string& temporary_path) {
    const int fd = open(temporary_path.c_str(), O_WRONLY | O_TRUNC);
    if (fd < 0) return Status::Error("cannot open " + temporary_path + " (" + ErrnoText() + ")");
    size_t written = 0;
    while (written < contents.size()) {
      const ssize_t n = ::write(fd, contents.data() + written, contents.size() - written);
      if (n < 0) {
        if (errno == EINTR) continue;
        const Status error = Status::Error("cannot write " + path + " (" + ErrnoText() + ")");
        close(fd);
        return error;
      }
      written += static_cast<size_t>(n);
    }
    if (fsync(fd) != 0 || close(fd) != 0) {
      return Status::Error("cannot flush " + path + " (" + ErrnoText() + ")");
    }
    return Status::Ok();
  });
}

Status WriteDirectoryAtomically(const std::string& dir, bool overwrite,
                                const std::function<Status(const std::string&)>& write) {
  namespace fs = std::filesystem;
  std::error_code error;
  std::string target = dir;
  while (target.size() > 1 && target.back() == '/') target.pop_back();
  const bool exists = fs::exists(target, error);
  if (exists && !fs::is_directory(target, error)) {
    return Status::Error(target + " exists and is not a folder");
  }
  if (exists && !fs::is_empty(target, error) && !overwrite) {
    return Status::Error(target + " exists and is not empty; pass --overwrite to replace it");
  }
  std::vector<char> pattern(target.begin(), target.end());
  const std::string suffix = ".tmp.XXXXXX";
  pattern.insert(pattern.end(), suffix.begin(), suffix.end());
  pattern.push_back('\0');
  if (mkdtemp(pattern.data()) == nullptr) {
    return Status::Error("cannot create a folder beside " + target + " (" + ErrnoText() +
                         "); check that the parent folder exists and is writable");
  }
  const std::string temporary_dir = pattern.data();
  chmod(temporary_dir.c_str(), 0755);
  Status status = write(temporary_dir);
  if (status.ok() && exists) {
    const std::string old_dir = temporary_dir + ".old";
    fs::rename(target, old_dir, error);
    if (!error) fs::rename(temporary_dir, target, error);
    if (error) {
      status = Status::Error("cannot replace " + target + " (" + error.message() + ")");
    } else {
      fs::remove_all(old_dir, error);
    }
  } else if (status.ok()) {
    fs::rename(temporary_dir, target, error);
    if (error) status = Status::Error("cannot create " + target + " (" + error.message() + ")");
  }
  if (!status.ok()) fs::remove_all(temporary_dir, error);
  return status;
}

}  // namespace accelcal
