#ifndef ACCELCAL_IO_CALIBRATION_STREAM_H_
#define ACCELCAL_IO_CALIBRATION_STREAM_H_

// Reads a tilt test from calibration.csv (theta,ax,ay) in fixed-size chunks and hands its
// samples on in batches, so that a test of any length is read in bounded memory: the
// closed-form baseline needs only its sufficient statistics (CalibrationAccumulator in
// estimation/tilt_table/linear_ls.h), never the samples themselves. A 10^8-sample file (5.6 GB of
// CSV at round-trip precision, 2.4 GB as three arrays of doubles) streams through 5 MB.
//
// The rules and the messages are ParseCsv's (io/csv_reader.h), from the same line parser
// (a last line without '\n' is refused as a file cut short), plus --theta_unit as
// LoadCalibrationTest applies it (io/course_data.h): the span check and the agreement of
// theta with the outputs' direction (io/theta_agreement.h), accumulated in the same pass.
// Before it opens the file, the path must be a regular file (CheckInputFile,
// io/input_file.h; no size cap, the point of streaming): a pipe such as bash's <(...) is
// refused by name rather than read as it comes. One rule is added to keep the memory
// bounded: a line longer than max_line_bytes is refused (a row is a few dozen bytes).
// Lines may end in "\n" or "\r\n" and may be split anywhere between reads.
//
// Memory is chunk_bytes + max_line_bytes for the reader (touched only as far as used),
// 24 * batch_samples bytes for a batch and 16 KiB for the agreement, whatever the file's
// size. The file is read with read(2), not mapped, so the page cache it passes through does
// not count as the process' resident memory.

#include <cstddef>
#include <functional>
#include <string>

#include "common/measurements.h"
#include "common/status.h"
#include "io/course_data.h"

namespace accelcal {

// Receives consecutive samples of the test, in file order, as a CalibrationTest of at most
// batch_samples samples (angles already in radians), valid only during the call. Being a
// CalibrationTest, a batch goes straight to CalibrationAccumulator::AddTest, the same code
// that accumulates a test held in memory.
using CalibrationSink = std::function<void(const CalibrationTest& batch)>;

struct CalibrationStreamOptions {
  AngleUnit theta_unit = AngleUnit::kAuto;
  size_t chunk_bytes = size_t{4} << 20;     // bytes asked of each read(2)
  size_t max_line_bytes = size_t{1} << 20;  // longer lines are refused
  // Samples per call of the sink (96 KB). A power of two, so that batches split the test
  // where CalibrationAccumulator::AddTest's blocks do and the streamed statistics equal those
  // of the test held in memory bit for bit.
  size_t batch_samples = 4096;
  // Whether theta must follow the outputs' direction (io/theta_agreement.h). Every reader of
  // a tilt test keeps it; only tests that compare the parser with ParseCsv on arbitrary
  // numbers turn it off.
  bool check_theta_agreement = true;
};

struct CalibrationStreamStats {
  long long samples = 0;
  long long lines = 0;  // including the header, comments and blank lines
  long long bytes = 0;  // read from the file
  double theta_min_rad = 0.0;
  double theta_max_rad = 0.0;
  // The agreement R of theta with the outputs' direction (io/theta_agreement.h), and under
  // AngleUnit::kAuto of the numbers read as degrees (0 otherwise).
  double theta_agreement = 0.0;
  double theta_agreement_as_degrees = 0.0;
  size_t reserved_bytes = 0;  // the reader's buffer, batch and agreement, the most it holds
};

// Streams the tilt test in `path` to `sink`. Failures carry the file name first, as
// LoadCalibrationTest's do. On failure the sink may already have seen part of the file
// (all of it when the angles are refused: their span and agreement are known only at the
// end), so whatever it built must be discarded. `stats` may be null.
Status StreamCalibrationCsv(const std::string& path, const CalibrationStreamOptions& options,
                            const CalibrationSink& sink, CalibrationStreamStats* stats);

}  // namespace accelcal

#endif  // ACCELCAL_IO_CALIBRATION_STREAM_H_
