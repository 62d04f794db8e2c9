#include "io/output_paths.h"

#include <sys/stat.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "io/atomic_file.h"

namespace accelcal {
namespace {

// The canonical form of an existing path (symbolic links resolved), or "".
std::string Canonical(const std::string& path) {
  char resolved[PATH_MAX];
  if (realpath(path.c_str(), resolved) == nullptr) return "";
  return resolved;
}

// Whether canonical `inner` is `outer` itself or lies inside it.
bool IsWithin(const std::string& inner, const std::string& outer) {
  if (inner == outer) return true;
  if (outer == "/") return true;
  return inner.size() > outer.size() && inner.compare(0, outer.size(), outer) == 0 &&
         inner[outer.size()] == '/';
}

const char* KindOf(mode_t mode) {
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  return "a file";
}

struct Resolved {
  std::string canonical;  // the output's canonical path, existing or not
  bool exists = false;
  struct stat info {};
};

Status Resolve(const OutputPath& output, Resolved* resolved) {
  std::string path = output.path;
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  const std::string where = output.flag + "=" + output.path;
  if (output.kind == OutputPath::Kind::kFile && output.path.back() == '/') {
    return Status::Error(where + " names a folder; name a file");
  }
  const size_t slash = path.find_last_of('/');
  const std::string parent =
      slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  if (name.empty() || name == "." || name == "..") {
    return Status::Error(where + " does not name a " +
                         (output.kind == OutputPath::Kind::kFile ? "file" : "folder") +
                         " of its own; give it a name");
  }
  const std::string canonical_parent = Canonical(parent);
  struct stat parent_info;
  if (canonical_parent.empty() || stat(canonical_parent.c_str(), &parent_info) != 0 ||
      !S_ISDIR(parent_info.st_mode)) {
    return Status::Error(where + ": the folder " + parent + " does not exist; create it first");
  }
  resolved->canonical = canonical_parent == "/" ? "/" + name : canonical_parent + "/" + name;
  if (lstat(path.c_str(), &resolved->info) == 0) {
    resolved->exists = true;
    const mode_t mode = resolved->info.st_mode;
    const bool right_kind = output.kind == OutputPath::Kind::kFile ? S_ISREG(mode) : S_ISDIR(mode);
    if (!right_kind) {
      return Status::Error(where + " exists and is " + KindOf(mode) + "; accelcal replaces only " +
                           (output.kind == OutputPath::Kind::kFile ? "regular files" : "folders") +
                           " it may write, so name a new " +
                           (output.kind == OutputPath::Kind::kFile ? "file" : "folder"));
    }
  } else if (errno != ENOENT) {
    return Status::Error(where + ": cannot check the path (" + std::strerror(errno) + ")");
  }
  return Status::Ok();
}

}  // namespace

Status CheckOutputPaths(const std::vector<OutputPath>& outputs, const RunInputs& inputs) {
  // The inputs as they are on disk: canonical paths and identities.
  struct Input {
    std::string shown;
    std::string canonical;
    struct stat info {};
    bool exists = false;
  };
  std::vector<Input> files;
  std::vector<Input> folders;
  for (const std::string& file : inputs.files) {
    if (file.empty()) continue;
    Input input{file, Canonical(file)};
    input.exists = stat(file.c_str(), &input.info) == 0;
    files.push_back(input);
  }
  for (const std::string& folder : inputs.folders) {
    if (folder.empty()) continue;
    Input input{folder, Canonical(folder)};
    if (!input.canonical.empty()) folders.push_back(input);
  }
  std::vector<std::string> seen;
  for (const OutputPath& output : outputs) {
    if (output.path.empty()) continue;
    Resolved resolved;
    ACCELCAL_RETURN_IF_ERROR(Resolve(output, &resolved));
    const std::string where = output.flag + "=" + output.path;
    for (const std::string& other : seen) {
      if (IsWithin(resolved.canonical, other) || IsWithin(other, resolved.canonical)) {
        return Status::Error(where +
                             " overlaps another output of this run; give each its own path");
      }
    }
    seen.push_back(resolved.canonical);
    for (const Input& input : files) {
      const bool same_file = resolved.exists && input.exists &&
                             resolved.info.st_dev == input.info.st_dev &&
                             resolved.info.st_ino == input.info.st_ino;
      if (same_file || (!input.canonical.empty() && resolved.canonical == input.canonical)) {
        return Status::Error(where + " is the input " + input.shown +
                             "; an output never replaces an input: name another file");
      }
      if (output.kind == OutputPath::Kind::kFolder && !input.canonical.empty() &&
          IsWithin(input.canonical, resolved.canonical)) {
        return Status::Error(where + " holds the input " + input.shown +
                             "; an output folder never contains the data it reads: name "
                             "another folder");
      }
    }
    for (const Input& folder : folders) {
      if (IsWithin(resolved.canonical, folder.canonical)) {
        return Status::Error(where + " lies inside the data folder " + folder.shown +
                             "; write outputs outside the data: name another path");
      }
      if (output.kind == OutputPath::Kind::kFolder &&
          IsWithin(folder.canonical, resolved.canonical)) {
        return Status::Error(where + " holds the data folder " + folder.shown +
                             "; an output folder never contains the data it reads: name "
                             "another folder");
      }
    }
  }
  return Status::Ok();
}

Status CheckFolderReplaceable(const std::string& dir, bool overwrite) {
  namespace fs = std::filesystem;
  std::error_code error;
  std::string target = dir;
  while (target.size() > 1 && target.back() == '/') target.pop_back();
  const fs::file_status existing = fs::symlink_status(target, error);
  const bool exists =
      existing.type() != fs::file_type::not_found && existing.type() != fs::file_type::none;
  if (!exists) return Status::Ok();
  if (existing.type() != fs::file_type::directory) {
    return Status::Error(target +
                         " exists and is not a folder (a file, a link or a device); "
                         "it is left as it is: name another folder");
  }
  if (fs::is_empty(target, error)) return Status::Ok();
  if (!overwrite) {
    return Status::Error(target +
                         " exists and is not empty; pass --overwrite to replace it "
                         "(only a folder accelcal wrote can be replaced)");
  }
  const fs::file_status marker = fs::symlink_status(target + "/" + kOutputFolderMarker, error);
  if (marker.type() != fs::file_type::regular) {
    return Status::Error(target + " was not written by accelcal (it has no " + kOutputFolderMarker +
                         " marker), so --overwrite will not delete it: name another folder, "
                         "or move it away yourself");
  }
  return Status::Ok();
}

}  // namespace accelcal
