#ifndef ACCELCAL_IO_LINE_STREAM_H_
#define ACCELCAL_IO_LINE_STREAM_H_

// A text file of any size, line by line, never held whole: the log readers (io/imu_log.h,
// io/imucal_session.h) parse each line as it comes, so memory is bounded by the longest line.
// The file must be a regular file (CheckInputFile, io/input_file.h). Every line must end in
// '\n': a last line without one is handed to `on_unterminated`, whose message (the caller's
// parser knows its line numbers and what a cut-short row looks like) is returned. A line
// longer than `max_line_bytes` is refused: no row of a log is that long, so the file is not
// what the caller reads. A file that changed from its opening to its end (a logger still
// appending) is refused, and a run that records its inputs' bytes (io/input_file.h) records the
// SHA-256 of the bytes streamed. Every failure, including those of the callbacks, starts with the
// file name.

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

#include "common/status.h"

namespace accelcal {

// `what` names the kind of file in messages ("an accelerometer log"). `on_line` sees each line
// without its '\n' (a '\r' before it stays: the CSV rules trim it); its failure stops the
// stream.
Status StreamTextLines(const std::string& path, const std::string& what, size_t max_line_bytes,
                       const std::function<Status(std::string_view line)>& on_line,
                       const std::function<Status(std::string_view rest)>& on_unterminated);

}  // namespace accelcal

#endif  // ACCELCAL_IO_LINE_STREAM_H_
