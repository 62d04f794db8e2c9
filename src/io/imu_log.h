#ifndef ACCELCAL_IO_IMU_LOG_H_
#define ACCELCAL_IO_IMU_LOG_H_

// Readers of a three-axis accelerometer log (common/triad_log.h), in one of two layouts,
// chosen by the file name, never guessed from the content:
//
//   - a name ending in ".csv": a CSV file whose header is t_s,acc_x,acc_y,acc_z
//     (io/csv_reader.h's rules: exactly 4 fields per row, '#' comments, blank lines);
//   - any other name: imu_tk's ASCII layout ("save -ascii" style, as its .mat example files
//     despite their suffix): no header, 4 numbers per line separated by blanks or tabs,
//     t [s] then x, y, z.
//
// The outputs are kept in whatever unit the sensor gives (raw counts in imu_tk's example);
// the calibration maps them to m/s^2. Every value must be a finite number; time must be
// strictly increasing, and its median step that of an accelerometer log (CheckLogTime,
// io/course_data.h), so a time axis in milliseconds is refused as such. A log read for
// calibration must also be evenly sampled (ImuLogSpacing::kEven), which one correcting sample
// by sample need not be. Every line ends in
// '\n' (a last line without one is a file cut short). Failures say "line N: what is wrong;
// what to do"; the callers add the file name (the Read and Stream functions add it).

#include <functional>
#include <string>
#include <string_view>

#include "common/status.h"
#include "common/triad_log.h"
#include "io/csv_reader.h"

namespace accelcal {

enum class ImuLogLayout { kWhitespace, kCsv };

// What a log's time steps must satisfy beyond increasing. kEven: no gap (a step above 10
// median steps: a pause, lost seconds, two recordings joined, inside which the sensor may have
// moved) and one rate (every block of a twentieth of the log, at least 100 steps, has its
// median step within 5% of the log's). Jitter and a few lost samples pass (imu_tk's Xsens log:
// steps in [0.9, 1.04] of the median; mimu4444: [0.98, 1.0001]). A calibration needs it: the
// static detector's windows and the noise model count samples, so a gap inside a pose or a
// change of rate weighs the pose wrongly, and the result looks fine. kAny: increasing only
// (apply corrects each sample on its own; allan checks the segments it uses).
enum class ImuLogSpacing { kEven, kAny };

// kCsv for a name ending in ".csv" (any case), kWhitespace otherwise.
ImuLogLayout ImuLogLayoutOf(const std::string& path);
const char* ImuLogLayoutName(ImuLogLayout layout);

// One line at a time, so that the whole and the streamed readers accept the same files.
class ImuLogLineParser {
 public:
  explicit ImuLogLineParser(ImuLogLayout layout);

  // Parses the next line (without its '\n'); *is_sample tells whether it held a sample,
  // then in t_s() and output(). Checks that time increases from the previous sample.
  Status ParseLine(std::string_view line, bool* is_sample);
  // After the last line: fails when the file held no sample (or, as CSV, no header).
  Status Finish() const;
  // The refusal of a last line without '\n'.
  Status UnterminatedLastLine(std::string_view rest) const;

  double t_s() const { return t_s_; }
  const std::array<double, 3>& output() const { return output_; }
  long long line_number() const { return line_number_; }

 private:
  Status ParseWhitespaceLine(std::string_view trimmed);
  Status CheckTime();

  ImuLogLayout layout_;
  CsvLineParser csv_;
  long long line_number_ = 0;
  long long sample_count_ = 0;
  double t_s_ = 0.0;
  double previous_t_s_ = 0.0;
  std::array<double, 3> output_{};
};

// The text of a log already in memory (tests, fuzzing): samples and the line checks, then
// CheckLogTime on the whole time axis.
Status ParseImuLog(std::string_view text, ImuLogLayout layout, TriadLog* log,
                   ImuLogSpacing spacing = ImuLogSpacing::kEven);

// Streams `path` in chunks of bounded size, handing the samples over in batches of at most
// `batch_samples`; `on_batch` sees each batch once. Memory is bounded whatever the file's
// size. Failures start with the file name. The median step is not checked here (it needs
// the whole axis); ReadImuLog checks it.
Status StreamImuLog(const std::string& path, size_t batch_samples,
                    const std::function<void(const TriadLog& batch)>& on_batch);

// The whole log, streamed into `log`, then CheckLogTime and `spacing`. Failures start with
// the file name.
Status ReadImuLog(const std::string& path, TriadLog* log,
                  ImuLogSpacing spacing = ImuLogSpacing::kEven);

}  // namespace accelcal

#endif  // ACCELCAL_IO_IMU_LOG_H_
