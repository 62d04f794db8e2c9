#ifndef ACCELCAL_IO_IMU_LOG_H_
#define ACCELCAL_IO_IMU_LOG_H_

// Readers of a three-axis IMU log (common/triad_log.h) in the layouts users record
// (docs/log-layouts.md), told from the content, never from the file's name:
//
//   - delimited text with a header naming the columns (',', ';' with a decimal comma or not,
//     tab, '|', blanks), after lines of metadata or not, with or without a time column (then
//     --rate_hz), time in s, ms, us or ns or a Unix time, the gyroscope's columns kept beside
//     the accelerometer's (io/imu_log_format.h decides the layout and the columns);
//   - imu_tk's ASCII layout ("save -ascii" style, as its .mat example files despite their
//     suffix): no header, 4 numbers per line separated by blanks or tabs, t [s] then x, y, z;
//   - a MATLAB .mat file (v5 or v7.3, io/mat_file.h) with the variables named: a time vector
//     and an N x 3 accelerometer (and gyroscope), or one vector per axis, or one N x 4 matrix
//     t, x, y, z;
//   - a ROS 2 bag's sensor_msgs/msg/Imu messages (io/ros2_bag.h), in m/s^2 and rad/s;
//   - imu_tk's pair of files (accelerometer and gyroscope, the same time stamps): the
//     gyroscope's file given apart (ImuLogReadOptions::gyroscope_path).
//
// The outputs are kept in whatever unit the sensor gives (raw counts in imu_tk's example);
// the calibration maps them to m/s^2. Every value used must be a finite number; time must be
// strictly increasing, and its median step that of an IMU log (CheckLogTime,
// io/course_data.h). A time column of host receive times in bursts is never the samples'
// times, whatever the use (ImuLogTiming). A log read for calibration must also be evenly sampled
// (ImuLogSpacing::kEven), which one correcting sample by sample need not be. Every line ends in
// '\n' (a last line without one is a file cut short). Failures say "line N: what is wrong;
// what to do" and start with the file's name.

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"
#include "io/host_time_bursts.h"
#include "io/imu_log_format.h"
#include "io/index_clock_fit.h"

namespace accelcal {

// What a log's time steps must satisfy beyond increasing. kEven: no gap (a step above 10
// median steps: a pause, lost seconds, two recordings joined, inside which the sensor may have
// moved) and one rate (every block of a twentieth of the log, at least 100 steps, has its
// median step within 5% of the log's). Jitter and a few lost samples pass (imu_tk's Xsens log:
// steps in [0.9, 1.04] of the median; mimu4444: [0.98, 1.0001]). A calibration needs it: the
// static detector's windows and the noise model count samples, so a gap inside a pose or a
// change of rate weighs the pose wrongly, and the result looks fine. kAny: increasing only
// (apply corrects each sample on its own; allan checks the segments it uses).
enum class ImuLogSpacing { kEven, kAny };

// How the samples' times were found (docs/log-layouts.md, "Time"; the JSON's log.time). A time
// column of host receive times in bursts (io/host_time_bursts.h) is never used as the samples'
// times: with a sample-number column they come from it at a rate fitted to the host's times
// (io/index_clock_fit.h); without one, or --rate_hz, the log is refused.
struct ImuLogTiming {
  // "time column", "row number and --rate_hz", "sample number and --rate_hz", "sample number and
  // a fitted rate"; "" for a ROS 2 bag's stamps (its notes say which).
  std::string from;
  std::string index_column;  // the sample-number column used, quoted, else ""
  // The time column's host receive times in bursts (bursts.bursty), else bursts.steps == 0.
  HostTimeBursts bursts;
  bool rate_fitted = false;
  IndexClockFit fit;               // when rate_fitted
  long long dropped_samples = -1;  // the index's jumps beyond 1, summed; -1: no index used
};

// How a log was read, for the report: the layout in one line, what the reader chose and why
// (each note a sentence to print), the metadata lines it skipped, the units the names state.
struct ImuLogSource {
  std::string layout;  // "whitespace ASCII (t [s], x, y, z)", "CSV (header ...)"
  std::vector<std::string> notes;
  std::vector<std::string> metadata;
  std::string accelerometer_unit;  // stated by the columns' names, else ""
  std::string gyroscope_unit;
  // What states those units when not the columns' names, as a sentence's subject and verb
  // ("sensor_msgs/msg/Imu (REP 145) says"), else "".
  std::string units_stated_by;
  std::string gyroscope_path;  // the paired file, when the gyroscope came from one
  // How time was read from a column: its name and its factor to seconds (empty name: time came
  // from the rate, or the layout defines it).
  std::string time_column;
  double time_scale_s = 1.0;
  ImuLogTiming timing;
  // The sample-number column, quoted ("'idx'", "column 2"), whether time came from it or not.
  std::string sample_number_column;
  // The samples' times need the whole log, which StreamImuLog, handing rows on as they come,
  // does not hold: time is a sample-number column over the rate, and ReadImuLog puts rows listed
  // out of order back in order (OrderBySampleNumber); or the time column holds host times in
  // bursts and a sample-number column is there to time them (StreamImuLog then fails, and
  // ReadImuLog fits the rate).
  bool times_need_whole_log = false;
};

// The text of a log already in memory (tests, fuzzing): the layout from the text, samples and
// the line checks, then CheckLogTime on the whole time axis. `source` may be null.
Status ParseImuLog(std::string_view text, const ImuLogReadOptions& options, TriadLog* log,
                   ImuLogSpacing spacing = ImuLogSpacing::kEven, ImuLogSource* source = nullptr);

// Streams a text log `path` in chunks of bounded size, handing the samples over in batches of
// at most `batch_samples`; `on_batch` sees each batch once. Memory is bounded whatever the
// file's size. Failures start with the file name. The median step is not checked here (it
// needs the whole axis); ReadImuLog checks it. Host times in bursts are: the batches have been
// handed on when they are known, and the call fails at the end, as ReadImuLog fails (or, with a
// sample-number column, ImuLogSource::times_need_whole_log says to read the log whole: the
// fitted rate needs all of it). A .mat file or a paired gyroscope file is refused here
// (ReadImuLog reads them whole).
Status StreamImuLog(const std::string& path, const ImuLogReadOptions& options, size_t batch_samples,
                    const std::function<void(const TriadLog& batch)>& on_batch,
                    ImuLogSource* source = nullptr);

// Whether StreamImuLog reads `path` as ReadImuLog does, sample for sample: a text log
// (neither a .mat file nor binary data) without a paired gyroscope file. A row order by sample
// number is only known once streaming starts (ImuLogSource::times_need_whole_log). False
// when the head cannot be read (ReadImuLog then says why).
bool StreamsLikeReadImuLog(const std::string& path, const ImuLogReadOptions& options);

// The whole log (a text log streamed, a .mat file through io/mat_file.h, the paired gyroscope
// file when options.gyroscope_path is set), then host times in bursts timed by the
// sample-number column or refused (ImuLogTiming, whatever `spacing`), then CheckLogTime and
// `spacing`. Failures start
// with the file name. `source` may be null.
Status ReadImuLog(const std::string& path, const ImuLogReadOptions& options, TriadLog* log,
                  ImuLogSpacing spacing = ImuLogSpacing::kEven, ImuLogSource* source = nullptr);

// The same with no option stated.
Status ReadImuLog(const std::string& path, TriadLog* log,
                  ImuLogSpacing spacing = ImuLogSpacing::kEven);

}  // namespace accelcal

#endif  // ACCELCAL_IO_IMU_LOG_H_
