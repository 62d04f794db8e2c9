#ifndef ACCELCAL_IO_ATOMIC_FILE_H_
#define ACCELCAL_IO_ATOMIC_FILE_H_

#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/status.h"

namespace accelcal {

// Writes `contents` to `path` so that `path` either keeps its old contents or holds the
// new ones whole: the bytes go to a temporary file in the same directory, which is
// flushed and renamed over `path`. A crash or a kill mid-write leaves no partial file, and
// an interruption by a signal leaves no temporary file either (io/cleanup.h). Only a
// regular file is ever replaced: a symbolic link, a device or a FIFO at `path` is refused
// (io/output_paths.h checks this before any work; this is the last line of defence).
Status WriteFileAtomically(const std::string& path, const std::string& contents);

// Several files, all or none: every file is written to its temporary sibling first, and
// only when all are written are they renamed into place.
Status WriteFilesAtomically(const std::vector<std::pair<std::string, std::string>>& files);

// The same for writers that need a file name of their own (e.g. libmatio): `write`
// receives the temporary path and returns a Status; on success the temporary file is
// renamed to `path`, on failure it is removed.
Status WriteAtomicallyWith(const std::string& path,
                           const std::function<Status(const std::string& temporary_path)>& write);

// The same for contents made piece by piece, a file too large to hold in memory (apply's
// output of a long log): `produce` calls `append` with each piece in order, and each goes to
// the temporary file as it comes. A failure of `produce` or of a write removes the temporary
// file and leaves `path` as it was, as a kill or a signal does.
using AppendFunction = std::function<Status(std::string_view piece)>;
Status WriteFileAtomicallyStreamed(
    const std::string& path, const std::function<Status(const AppendFunction& append)>& produce);

// The name of the marker file accelcal writes into every folder it creates.
extern const char kOutputFolderMarker[];

// The same for a whole folder: `write` fills a temporary sibling of `dir` (which receives
// the marker file), which then replaces `dir`. An existing non-empty `dir` is replaced only
// with `overwrite` and only when it carries the marker, i.e. when accelcal wrote it; on any
// failure the temporary folder is removed and `dir` is left as it was.
Status WriteDirectoryAtomically(
    const std::string& dir, bool overwrite,
    const std::function<Status(const std::string& temporary_dir)>& write);

}  // namespace accelcal

#endif  // ACCELCAL_IO_ATOMIC_FILE_H_
