#ifndef ACCELCAL_IO_IMUCAL_SESSION_H_
#define ACCELCAL_IO_IMUCAL_SESSION_H_

// Reader of imucal's annotated Ferraris session (common/ferraris_session.h, docs/imucal.md): a
// CSV file whose header is
//
//   part,samples,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z
//
// one row per sample: `part` the section's label (x_p, x_a, y_p, y_a, z_p, z_a, x_rot, y_rot,
// z_rot), `samples` the sample's index in the recording, then the accelerometer's and the
// gyroscope's outputs in whatever unit the sensor gives (raw counts in imucal's example).
// io/csv_reader.h's rules apply (exactly 8 fields, finite numbers, '#' comments, blank lines,
// every line ending in '\n'). A section's rows need not be contiguous: as in imucal, a label
// gathers every row that carries it. Refused, with the file and line: a label that is not one
// of the nine, an empty label, a value that is not a finite number; after the last line, a
// section with no rows. The file is streamed (io/line_stream.h): each section is kept as its
// count, means and sample variances, never as its rows.

#include <string>
#include <string_view>

#include "common/ferraris_session.h"
#include "common/status.h"

namespace accelcal {

// The text of a session already in memory (tests, fuzzing). Failures say "line N...".
Status ParseImucalSession(std::string_view text, FerrarisSession* session);

// The file `path`; failures start with the file name.
Status ReadImucalSession(const std::string& path, FerrarisSession* session);

}  // namespace accelcal

#endif  // ACCELCAL_IO_IMUCAL_SESSION_H_
