#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include "io/cleanup.h"
#include "io/output_paths.h"

namespace accelcal {

const char kOutputFolderMarker[] = ".accelcal-output";

namespace {

std::string ErrnoText() { return std::strerror(errno); }

// Refuses to replace anything but a regular file (or nothing).
Status CheckReplaceable(const std::string& path) {
  struct stat info;
  if (lstat(path.c_str(), &info) != 0) return Status::Ok();
  if (S_ISREG(info.st_mode)) return Status::Ok();
  return Status::Error(path + " exists and is not a regular file (" +
                       (S_ISLNK(info.st_mode) ? "a symbolic link" : "a folder or a special file") +
                       "); it is left as it is: name another file");
}

// Creates an empty temporary file beside `path`, registered for cleanup; returns its name.
Status MakeTemporarySibling(const std::string& path, std::string* temporary_path) {
  std::vector<char> name(path.begin(), path.end());
  const std::string suffix = ".tmp.XXXXXX";
  name.insert(name.end(), suffix.begin(), suffix.end());
  name.push_back('\0');
  int fd = -1;
  WithCleanupHeld([&] {
    fd = mkstemp(name.data());
    if (fd >= 0) RegisterTemporary(name.data());
  });
  if (fd < 0) {
    return Status::Error("cannot create a file beside " + path + " (" + ErrnoText() +
                         "); check that the directory exists and is writable");
  }
  close(fd);
  *temporary_path = name.data();
  return Status::Ok();
}

void RemoveTemporary(const std::string& temporary_path) {
  std::remove(temporary_path.c_str());
  ForgetTemporary(temporary_path);
}

// mkstemp creates 0600; outputs are ordinary files a user's other tools can read.
void MakeReadable(const std::string& temporary_path) {
  const mode_t mask = umask(0);
  umask(mask);
  chmod(temporary_path.c_str(), 0666 & ~mask);
}

// Writes all of `contents` to `fd`, retrying after a signal.
Status WriteAll(int fd, const std::string& path, std::string_view contents) {
  size_t written = 0;
  while (written < contents.size()) {
    const ssize_t n = ::write(fd, contents.data() + written, contents.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      return Status::Error("cannot write " + path + " (" + ErrnoText() + ")");
    }
    written += static_cast<size_t>(n);
  }
  return Status::Ok();
}

// Opens the temporary file, lets `write` fill it through `fd`, then flushes and closes it.
Status WriteThroughFd(const std::string& path, const std::string& temporary_path,
                      const std::function<Status(int fd)>& write) {
  const int fd = open(temporary_path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) return Status::Error("cannot open " + temporary_path + " (" + ErrnoText() + ")");
  Status status = write(fd);
  if (status.ok() && fsync(fd) != 0)
    status = Status::Error("cannot flush " + path + " (" + ErrnoText() + ")");
  if (close(fd) != 0 && status.ok())
    status = Status::Error("cannot flush " + path + " (" + ErrnoText() + ")");
  return status;
}

Status WriteContents(const std::string& path, const std::string& temporary_path,
                     const std::string& contents) {
  return WriteThroughFd(path, temporary_path, [&](int fd) { return WriteAll(fd, path, contents); });
}

// Renames a finished temporary file over `path`.
Status Commit(const std::string& path, const std::string& temporary_path) {
  ACCELCAL_RETURN_IF_ERROR(CheckReplaceable(path));
  MakeReadable(temporary_path);
  Status status;
  WithCleanupHeld([&] {
    if (std::rename(temporary_path.c_str(), path.c_str()) != 0) {
      status = Status::Error("cannot rename " + temporary_path + " to " + path + " (" +
                             ErrnoText() + ")");
    } else {
      ForgetTemporary(temporary_path);
    }
  });
  return status;
}

}  // namespace

Status WriteAtomicallyWith(const std::string& path,
                           const std::function<Status(const std::string&)>& write) {
  ACCELCAL_RETURN_IF_ERROR(CheckReplaceable(path));
  std::string temporary_path;
  ACCELCAL_RETURN_IF_ERROR(MakeTemporarySibling(path, &temporary_path));
  Status status = write(temporary_path);
  if (status.ok()) status = Commit(path, temporary_path);
  if (!status.ok()) RemoveTemporary(temporary_path);
  return status;
}

Status WriteFileAtomically(const std::string& path, const std::string& contents) {
  return WriteAtomicallyWith(path, [&](const std::string& temporary_path) {
    return WriteContents(path, temporary_path, contents);
  });
}

Status WriteFileAtomicallyStreamed(const std::string& path,
                                   const std::function<Status(const AppendFunction&)>& produce) {
  return WriteAtomicallyWith(path, [&](const std::string& temporary_path) {
    return WriteThroughFd(path, temporary_path, [&](int fd) {
      return produce([&](std::string_view piece) { return WriteAll(fd, path, piece); });
    });
  });
}

Status WriteFilesAtomically(const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<std::string> temporaries;
  Status status;
  for (const auto& [path, contents] : files) {
    status = CheckReplaceable(path);
    std::string temporary_path;
    if (status.ok()) status = MakeTemporarySibling(path, &temporary_path);
    if (!status.ok()) break;
    temporaries.push_back(temporary_path);
    status = WriteContents(path, temporary_path, contents);
    if (!status.ok()) break;
  }
  for (size_t k = 0; status.ok() && k < files.size(); ++k) {
    status = Commit(files[k].first, temporaries[k]);
  }
  if (!status.ok()) {
    for (const std::string& temporary_path : temporaries) RemoveTemporary(temporary_path);
  }
  return status;
}

Status WriteDirectoryAtomically(const std::string& dir, bool overwrite,
                                const std::function<Status(const std::string&)>& write) {
  namespace fs = std::filesystem;
  std::error_code error;
  std::string target = dir;
  while (target.size() > 1 && target.back() == '/') target.pop_back();
  // One rule for every writer of a folder (io/output_paths.h), checked again here, at the
  // last moment, in case the folder changed since the writer's own check.
  ACCELCAL_RETURN_IF_ERROR(CheckFolderReplaceable(target, overwrite));
  const fs::file_status existing = fs::symlink_status(target, error);
  const bool exists =
      existing.type() != fs::file_type::not_found && existing.type() != fs::file_type::none;
  std::vector<char> pattern(target.begin(), target.end());
  const std::string suffix = ".tmp.XXXXXX";
  pattern.insert(pattern.end(), suffix.begin(), suffix.end());
  pattern.push_back('\0');
  bool created = false;
  WithCleanupHeld([&] {
    created = mkdtemp(pattern.data()) != nullptr;
    if (created) RegisterTemporary(pattern.data());
  });
  if (!created) {
    return Status::Error("cannot create a folder beside " + target + " (" + ErrnoText() +
                         "); check that the parent folder exists and is writable");
  }
  const std::string temporary_dir = pattern.data();
  chmod(temporary_dir.c_str(), 0755);
  Status status = WriteFileAtomically(temporary_dir + "/" + kOutputFolderMarker,
                                      "This folder was written by accelcal; accelcal's "
                                      "--overwrite may replace it.\n");
  if (status.ok()) status = write(temporary_dir);
  if (status.ok()) {
    const std::string old_dir = temporary_dir + ".old";
    // The swap runs with the cleanup held: an interruption sees the old folder in place, or
    // the new one in place and the old one registered for removal.
    // Where the file system can, the two folders trade places in one step (renameat2's
    // RENAME_EXCHANGE), so that even a SIGKILL, which no handler holds, finds the old folder or
    // the new one at `target`; the old one is then the temporary folder, removed below.
    bool exchanged = false;
    WithCleanupHeld([&] {
      if (exists && renameat2(AT_FDCWD, temporary_dir.c_str(), AT_FDCWD, target.c_str(),
                              RENAME_EXCHANGE) == 0) {
        exchanged = true;
      } else if (exists) {
        fs::rename(target, old_dir, error);
        if (!error) {
          RegisterTemporary(old_dir);
          fs::rename(temporary_dir, target, error);
          if (error) fs::rename(old_dir, target, error), ForgetTemporary(old_dir);
        }
      } else {
        fs::rename(temporary_dir, target, error);
      }
      if (error) {
        status = Status::Error("cannot " + std::string(exists ? "replace " : "create ") + target +
                               " (" + error.message() + ")");
      } else if (!exchanged) {
        ForgetTemporary(temporary_dir);
      }
    });
    if (exchanged) {  // the temporary folder holds the old output now
      fs::remove_all(temporary_dir, error);
      ForgetTemporary(temporary_dir);
    } else if (status.ok() && exists) {
      fs::remove_all(old_dir, error);
      ForgetTemporary(old_dir);
    }
  }
  if (!status.ok()) {
    fs::remove_all(temporary_dir, error);
    ForgetTemporary(temporary_dir);
  }
  return status;
}

}  // namespace accelcal
