#ifndef ACCELCAL_IO_OUTPUT_PATHS_H_
#define ACCELCAL_IO_OUTPUT_PATHS_H_

// Where a binary may write. An output never destroys the user's data or a special file:
// every output path is checked, before any work is done, against the inputs of the run
// and against what is already there. An output is refused when it
//   - is an input file (by path or by identity: a hard link is the same file),
//   - lies inside an input folder (a --data_dir), or, for a folder, is or contains an input,
//   - exists and is a symbolic link, a device (/dev/null), a FIFO, a socket, or, for a file,
//     a folder (and for a folder, a file),
//   - has no existing parent folder, or is named twice in one run.
// Replacing an existing folder additionally needs --overwrite and the folder to carry the
// marker that accelcal writes into every folder it creates (io/atomic_file.h), so that
// --overwrite can never delete a folder that accelcal did not write.

#include <string>
#include <vector>

#include "common/status.h"

namespace accelcal {

struct RunInputs {
  std::vector<std::string> files;    // every file the run reads
  std::vector<std::string> folders;  // every folder it reads from (--data_dir)
};

struct OutputPath {
  enum class Kind { kFile, kFolder };
  std::string flag;  // e.g. "--json", for the message
  std::string path;  // empty: not requested
  Kind kind = Kind::kFile;
};

// Checks every requested output of `outputs` (empty paths are skipped) as described above.
Status CheckOutputPaths(const std::vector<OutputPath>& outputs, const RunInputs& inputs);

// Whether io/atomic_file.h's WriteDirectoryAtomically may write the folder `dir`: it does not
// exist, or is an empty folder, or (with `overwrite`) a folder that carries accelcal's marker.
// Refused otherwise (a file, a link or a device; a folder with something in it and no
// --overwrite; one accelcal did not write). The same check WriteDirectoryAtomically makes, for a
// writer to make it before any work, as every writer checks its paths (CheckOutputPaths).
Status CheckFolderReplaceable(const std::string& dir, bool overwrite);

}  // namespace accelcal

#endif  // ACCELCAL_IO_OUTPUT_PATHS_H_
