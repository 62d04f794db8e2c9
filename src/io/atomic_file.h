#ifndef ACCELCAL_IO_ATOMIC_FILE_H_
#define ACCELCAL_IO_ATOMIC_FILE_H_

#include <functional>
#include <string>

#include "common/status.h"

namespace accelcal {

// Writes `contents` to `path` so that `path` either keeps its old contents or holds the
// new ones whole: the bytes go to a temporary file in the same directory, which is
// flushed and renamed over `path`. A crash or a kill mid-write leaves no partial file.
Status WriteFileAtomically(const std::string& path, const std::string& contents);

// The same for writers that need a file name of their own (e.g. libmatio): `write`
// receives the temporary path and returns a Status; on success the temporary file is
// renamed to `path`, on failure it is removed.
Status WriteAtomicallyWith(const std::string& path,
                           const std::function<Status(const std::string& temporary_path)>& write);

// The same for a whole folder: `write` fills a temporary sibling of `dir`, which then
// replaces `dir`. An existing non-empty `dir` is replaced only with `overwrite`; on any
// failure the temporary folder is removed and `dir` is left as it was.
Status WriteDirectoryAtomically(
    const std::string& dir, bool overwrite,
    const std::function<Status(const std::string& temporary_dir)>& write);

}  // namespace accelcal

#endif  // ACCELCAL_IO_ATOMIC_FILE_H_
