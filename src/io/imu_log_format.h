#ifndef ACCELCAL_IO_IMU_LOG_FORMAT_H_
#define ACCELCAL_IO_IMU_LOG_FORMAT_H_

// How a three-axis IMU log is laid out, told from its first lines (docs/log-layouts.md has the
// table of layouts, with an example each). io/imu_log.h reads the samples with the format this
// decides; this file only looks at the head of the file and at the column names.
//
// Text logs. The first data row is the first line that, with the next rows, splits into the
// same number (2 or more) of fields, most of them numbers, with one separator: ',' then ';',
// tab, '|', then runs of blanks (imu_tk's layout). With ';' a number may use a decimal comma
// (9,81). The line just before the data, '#' comment or not, is the header when it splits
// into as many fields and one of them is not a number (EuRoC and Kalibr write
// "#timestamp [ns],w_RS_S_x [rad s^-1],..."); the lines before the header are metadata
// ("Fs,100", a device name), kept to be echoed in the report.
//
// Columns are chosen by name (ClassifyImuColumnName: the alias table), or by --columns. Time:
// t, time, timestamp, stamp, ... with its unit from the name ("t_s", "time_ms",
// "timestamp [ns]", "Time (us)"), from --time_unit, or inferred from the median step, and
// said so. A sample-number column (samples, n_samples, index, ...) or the row order gives time
// with --rate_hz. An accelerometer is three columns of one family (a, acc, accel,
// accelerometer, acceleration, linear_acceleration) with the axes x, y, z ("ax", "acc_x",
// "ACCEL_X", "AccX", "a_RS_S_x", "field.linear_acceleration.x"); a gyroscope likewise (g, gyr,
// gyro, gyroscope, w, omega, angular_velocity). Several complete accelerometers in one file
// (ACCEL_BMI160_0_X and ACCEL_BMI160_1_X) are refused, listing them: a file is never read
// from one chosen silently. A headerless file of 4 numbers per row is imu_tk's t, x, y, z.
//
// Every failure is one line naming the line or column and what to give.

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "common/status.h"

namespace accelcal {

// What a column of a log is, by its name.
enum class ImuColumnKind { kOther, kTime, kSampleIndex, kAccelerometer, kGyroscope };

struct ImuColumnName {
  ImuColumnKind kind = ImuColumnKind::kOther;
  int axis = -1;           // 0, 1, 2 for x, y, z (accelerometer and gyroscope)
  std::string device;      // what else the name says ("bmi160_0"): one device per value
  std::string time_unit;   // "s", "ms", "us", "ns" when the name states it, else ""
  std::string value_unit;  // "m/s^2", "g", "rad/s", "deg/s" when the name states it, else ""
};

ImuColumnName ClassifyImuColumnName(std::string_view name);

// The time axis's unit: its factor to seconds; false for another text.
bool TimeUnitToSeconds(std::string_view unit, double* seconds);

// What the user may state (flags --columns, --rate_hz, --time_unit).
struct ImuLogReadOptions {
  // "t:TIME,ax:ACC_X,ay:ACC_Y,az:ACC_Z,gx:...": keys t, index, ax, ay, az, gx, gy, gz; a value
  // is a header name (exact, then ignoring case) or a column number from 1. In a .mat file a
  // value is a variable (a vector) or a column of one, NAME(:,K); keys acc and gyr take an
  // N x 3 variable. Keys not given are chosen by name, as without the flag.
  std::string columns;
  double rate_hz = 0.0;   // > 0: time is the row's number (or the sample-number column) / rate
  std::string time_unit;  // "" (stated by the name, or inferred), or s, ms, us, ns
  // imu_tk's pair of files: the gyroscope's file, with the accelerometer's time stamps.
  std::string gyroscope_path;
  // Set by the reader for that file: its triad is the gyroscope (named gyr_x, ... or not).
  bool gyroscope_file = false;
  // A ROS 2 bag (io/ros2_bag.h): the sensor_msgs/msg/Imu topic (--topic; empty: the bag's one
  // Imu topic) and the time read, "header" (the messages' stamps) or "receive" (--bag_time).
  std::string topic;
  std::string bag_time = "header";
};

// --columns parsed: key -> value, in the order given. Refuses an unknown key, a key twice, an
// empty value.
struct ImuColumnChoice {
  std::string key;
  std::string value;
};
Status ParseImuColumnChoices(const std::string& text, std::vector<ImuColumnChoice>* choices);

// A delimited text log's layout, as decided from its head.
struct ImuTextFormat {
  char separator = ' ';        // ',', ';', '\t', '|', or ' ' for runs of blanks and tabs
  bool decimal_comma = false;  // with ';': 9,81
  long long header_line = 0;   // 0: none
  long long first_data_line = 0;
  int field_count = 0;
  std::vector<std::string> header;    // the header's fields (trimmed, unquoted), or empty
  std::vector<std::string> metadata;  // the lines before the header, as written (bounded)
  int time_column = -1;               // field indices from 0, -1: none
  int index_column = -1;
  std::array<int, 3> accelerometer{-1, -1, -1};
  std::array<int, 3> gyroscope{-1, -1, -1};
  // Time in seconds = (value - origin) * time_scale_s; origin is the first sample's value when
  // the time axis is a Unix epoch (rebased, and said), else 0. With rate_hz, time comes from
  // the row (or the sample number) instead.
  double time_scale_s = 1.0;
  bool epoch = false;
  double rate_hz = 0.0;
  std::string time_rule;           // how time was found, in words ("" for imu_tk's own layout)
  std::string accelerometer_unit;  // stated by the columns' names, else ""
  std::string gyroscope_unit;
  std::vector<std::string> notes;  // what the reader chose and why, to be printed
  std::string description;         // one line: layout and columns
};

// Decides the format of a text log from `head`, its first bytes (the whole file when short;
// `whole` says whether it is). Failures say what is wrong with the line or the columns.
Status DetectImuTextFormat(std::string_view head, bool whole, const ImuLogReadOptions& options,
                           ImuTextFormat* format);

// The time unit from the median step of the head's time values (raw, in the column's unit),
// when neither the name nor --time_unit states it: the one unit in which the step is that of
// an IMU (1 Hz to 100 kHz; of two, the one within 10 Hz to 2 kHz). Fills the format's scale
// and rule, or fails asking for --time_unit or --rate_hz. A time that counts 0, 1, 2, ... is a
// sample number, refused. `seconds_by_layout`: the layout defines seconds (imu_tk's), which
// stand, unsaid, when they give an IMU's rate.
Status InferTimeUnit(const std::vector<double>& head_times, const std::string& column,
                     bool seconds_by_layout, ImuTextFormat* format);

// The time axis's unit, in order: --time_unit (`flag_unit`), the unit the column's name states
// (`named_unit`), else InferTimeUnit on the first values; then a time beyond 1e8 s (a clock's
// epoch) is counted from the first sample (format->epoch), and a note gives its start. `label`
// names the column in the notes and messages.
Status ChooseTimeUnit(const std::vector<double>& head_times, const std::string& label,
                      const std::string& named_unit, const std::string& flag_unit,
                      bool seconds_by_layout, ImuTextFormat* format);

// The time units by index (0: s, 1: ms, 2: us, 3: ns), and those in which a step of `raw_step`
// (the time column's own numbers) is an IMU log's (1 Hz to 100 kHz, CheckLogTime's bounds).
constexpr const char* kTimeUnits[] = {"s", "ms", "us", "ns"};
std::vector<int> TimeUnitsForStep(double raw_step);
// Of two such units, the one at a usual IMU rate (20 Hz to 2 kHz) when only one is; else `units`.
std::vector<int> PreferUsualRate(double raw_step, const std::vector<int>& units);

// A line trimmed of blanks, tabs and '\r' (not of quotes: those belong to its first and last
// fields).
std::string_view TrimLine(std::string_view text);

// The refusal of a last line without '\n' (line `line_number`): a file cut short.
Status CutShortLine(long long line_number);

// The splitting of a data line by the format's separator (fields trimmed of blanks, '\r' and
// double quotes).
void SplitImuFields(std::string_view line, char separator, std::vector<std::string_view>* fields);

// What an N x 3 variable of a .mat file holds, by its name: kAccelerometer ("acc", "accel",
// "accelerometer", "a"), kGyroscope ("gyr", "gyro", "omega", "w"), kTime, kSampleIndex, or
// kOther; a vector's name is classified as a column's.
ImuColumnKind ClassifyImuVariableName(std::string_view name);

}  // namespace accelcal

#endif  // ACCELCAL_IO_IMU_LOG_FORMAT_H_
