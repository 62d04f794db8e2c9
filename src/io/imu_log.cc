#include "io/imu_log.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <vector>

#include "common/format.h"
#include "common/statistics.h"
#include "io/course_data.h"
#include "io/csv_reader.h"
#include "io/input_file.h"
#include "io/input_text.h"
#include "io/line_stream.h"
#include "io/mat_file.h"
#include "io/ros2_bag.h"

namespace accelcal {
namespace {

constexpr size_t kMaxLineBytes = 1 << 16;
// The head the layout is decided from: the first lines of the file, up to this many bytes.
constexpr size_t kHeadBytes = 1 << 18;

std::string Where(long long line_number) { return "line " + std::to_string(line_number); }

// The decimal numbers of a typical log ("3.3108000e+04": at most 19 digits and a small
// exponent) by Clinger's fast path: when the digits form an integer m <= 2^53 and the
// exponent e is within +-22, m and 10^|e| are exact doubles, so m * 10^e (or m / 10^-e) is
// one correctly rounded operation, the very double std::from_chars gives, at a fraction of
// its cost. Reads from `*p` up to the first character that cannot continue the number and
// leaves `*p` there; false for anything else (other forms, more digits, no digits), which
// the caller then leaves to ParseFiniteNumber, the arbiter of what a number is.
bool ReadShortDecimal(const char** p, const char* end, double* value) {
  static constexpr double kPowersOfTen[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                            1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                            1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  constexpr long kMaxDigits = 19;  // digits, leading zeros included: below 10^19 < 2^64
  constexpr uint64_t kMaxExactInteger = uint64_t{1} << 53;
  auto is_digit = [](char c) { return static_cast<unsigned char>(c - '0') < 10; };
  const char* q = *p;
  bool negative = false;
  if (q < end && (*q == '-' || *q == '+')) negative = *q++ == '-';
  uint64_t mantissa = 0;  // wraps past kMaxDigits digits, which are then refused
  const char* const integer = q;
  for (; q < end && is_digit(*q); ++q) mantissa = mantissa * 10 + (*q - '0');
  long digits = q - integer;
  int exponent = 0;
  if (q < end && *q == '.') {
    const char* const fraction = ++q;
    for (; q < end && is_digit(*q); ++q) mantissa = mantissa * 10 + (*q - '0');
    exponent = -static_cast<int>(q - fraction);
    digits += q - fraction;
  }
  if (digits == 0 || digits > kMaxDigits || mantissa > kMaxExactInteger) return false;
  if (q < end && (*q == 'e' || *q == 'E')) {
    ++q;
    bool negative_exponent = false;
    if (q < end && (*q == '-' || *q == '+')) negative_exponent = *q++ == '-';
    const char* const written = q;
    int magnitude = 0;
    for (; q < end && is_digit(*q) && q - written < 4; ++q) magnitude = magnitude * 10 + (*q - '0');
    if (q == written || (q < end && is_digit(*q))) return false;
    exponent += negative_exponent ? -magnitude : magnitude;
  }
  if (exponent < -22 || exponent > 22) return false;
  const double m = static_cast<double>(mantissa);
  const double magnitude = exponent < 0 ? m / kPowersOfTen[-exponent] : m * kPowersOfTen[exponent];
  *value = negative ? -magnitude : magnitude;
  *p = q;
  return true;
}

// A whole cell by ReadShortDecimal.
bool ParseShortDecimal(std::string_view text, double* value) {
  const char* p = text.data();
  const char* const end = p + text.size();
  return ReadShortDecimal(&p, end, value) && p == end;
}

bool IsBlank(char c) { return c == ' ' || c == '\t'; }

// A row of four short decimals separated by blanks, in one pass; false for anything else,
// which the caller parses field by field (and explains).
bool ReadFourShortDecimals(std::string_view trimmed, double values[4]) {
  const char* p = trimmed.data();
  const char* const end = p + trimmed.size();
  for (int c = 0; c < 4; ++c) {
    if (c > 0) {
      if (p == end || !IsBlank(*p)) return false;
      while (p < end && IsBlank(*p)) ++p;
    }
    if (!ReadShortDecimal(&p, end, &values[c])) return false;
  }
  return p == end;
}

// ImuLogSpacing::kEven's rule on a time axis whose median step CheckLogTime gave: no step
// above kMaxGapSteps median steps (a gap), and no block of consecutive steps whose median
// step is more than kMaxRateChange from the log's (a change of rate). Jitter and a few lost
// samples pass: a pose's mean and variance are those of the samples it holds. Host stamps in
// bursts never reach it (TimeTheSamples, for every spacing).
constexpr double kMaxGapSteps = 10.0;
constexpr double kMaxRateChange = 0.05;
constexpr size_t kMinRateBlock = 100;

Status CheckEvenSpacing(const std::vector<double>& timestamp_s, double median_step_s) {
  const size_t steps = timestamp_s.size() - 1;
  for (size_t j = 1; j <= steps; ++j) {
    const double step_s = timestamp_s[j] - timestamp_s[j - 1];
    if (step_s <= kMaxGapSteps * median_step_s) continue;
    return Status::Error(StringPrintf(
        "sample %zu (t = %.9g s) follows the previous one by %.6g s, %.4g times the log's median "
        "step of %.6g s: the log has a gap (lost samples, a pause, or two recordings joined), "
        "inside which the sensor may have moved; calibrate from the part before or after the "
        "gap, or record the session again",
        j + 1, timestamp_s[j], step_s, step_s / median_step_s, median_step_s));
  }
  // Blocks of a twentieth of the log (at least kMinRateBlock steps); the last one takes the rest.
  const size_t block = std::max(kMinRateBlock, steps / 20);
  std::vector<double> block_steps;
  for (size_t first = 1; first + block / 2 <= steps + 1; first += block) {
    const size_t last = first + block > steps + 1 - block / 2 ? steps : first + block - 1;
    block_steps.clear();
    for (size_t j = first; j <= last; ++j)
      block_steps.push_back(timestamp_s[j] - timestamp_s[j - 1]);
    const double block_median_s = UpperMedian(block_steps);
    if (std::abs(block_median_s - median_step_s) > kMaxRateChange * median_step_s) {
      return Status::Error(StringPrintf(
          "the sampling rate changes within the log: from sample %zu to %zu (t = %.9g to %.9g s) "
          "the median step is %.6g s, against %.6g s over the log; a calibration needs one rate "
          "(its static detector and noise model count samples): resample the log to one rate, "
          "or cut it where the rate changes",
          first, last + 1, timestamp_s[first - 1], timestamp_s[last], block_median_s,
          median_step_s));
    }
    if (last == steps) break;
  }
  return Status::Ok();
}

Status CheckSpacing(const std::vector<double>& timestamp_s, ImuLogSpacing spacing) {
  double step_s = 0.0;
  ACCELCAL_RETURN_IF_ERROR(CheckLogTime(timestamp_s, "t", &step_s));
  return spacing == ImuLogSpacing::kEven ? CheckEvenSpacing(timestamp_s, step_s) : Status::Ok();
}

// The data lines of a text log, in the format DetectImuTextFormat decided.
class ImuLogLineParser {
 public:
  // `reorder`: time from a sample-number column need not increase row by row; the caller
  // orders the rows by it (ReadImuLog).
  ImuLogLineParser(const ImuTextFormat& format, bool reorder)
      : format_(format), reorder_(reorder && format.index_column >= 0 && format.rate_hz > 0.0) {
    imu_tk_fast_ = format.separator == ' ' && format.field_count == 4 && format.time_column == 0 &&
                   format.accelerometer == std::array<int, 3>{1, 2, 3} && !format.epoch &&
                   format.time_scale_s == 1.0 && format.rate_hz == 0.0;
  }

  // Parses the next line (without its '\n'); *is_sample tells whether it held a sample, then
  // in t_s(), accelerometer() and gyroscope(). Checks that time increases.
  Status ParseLine(std::string_view line, bool* is_sample);
  Status Finish() const {
    if (sample_count_ == 0)
      return Status::Error("no samples: the file has a header but no data rows");
    return Status::Ok();
  }
  Status UnterminatedLastLine() const { return CutShortLine(line_number_ + 1); }
  double t_s() const { return t_s_; }
  const std::array<double, 3>& accelerometer() const { return accelerometer_; }
  const std::array<double, 3>& gyroscope() const { return gyroscope_; }
  // The sample-number column's value when time comes from a time column (NaN when the cell is
  // no number: the column is then of no use to time host stamps in bursts, and
  // FitIndexClock says so).
  double sample_number() const { return sample_number_; }

 private:
  Status Cell(int column, const char* role, double* value) const;
  Status CheckTime();

  const ImuTextFormat& format_;
  const bool reorder_;
  bool imu_tk_fast_ = false;
  std::vector<std::string_view> fields_;
  long long line_number_ = 0;
  long long sample_count_ = 0;
  double t_s_ = 0.0;
  double previous_t_s_ = 0.0;
  double time_origin_ = 0.0;
  bool integer_time_ = false;  // this row's time cell is an integer (integer_time_value_)
  long long integer_time_value_ = 0;
  bool integer_origin_ = false;
  long long integer_time_origin_ = 0;
  double sample_number_ = std::numeric_limits<double>::quiet_NaN();
  std::array<double, 3> accelerometer_{};
  std::array<double, 3> gyroscope_{};
};

Status ImuLogLineParser::Cell(int column, const char* role, double* value) const {
  const std::string_view cell = fields_[column];
  if (!format_.decimal_comma && ParseShortDecimal(cell, value)) return Status::Ok();
  bool parsed = false;
  if (format_.decimal_comma) {
    std::string copy(cell);
    std::replace(copy.begin(), copy.end(), ',', '.');
    parsed = ParseFiniteNumber(copy, value);
  } else {
    parsed = ParseFiniteNumber(cell, value);
  }
  if (parsed) return Status::Ok();
  if (!format_.header.empty() && fields_.size() <= format_.header.size() &&
      std::equal(fields_.begin(), fields_.end(), format_.header.begin())) {
    return Status::Error(StringPrintf(
        "%s repeats the header of line %lld: two logs joined in one file? split it there and "
        "calibrate each part",
        Where(line_number_).c_str(), format_.header_line));
  }
  const std::string where =
      format_.header.empty() ? StringPrintf("column %d (%s)", column + 1, role)
                             : "column '" + EchoInput(format_.header[column]) + "' (" + role + ")";
  return Status::Error(Where(line_number_) + ", " + where + ": '" + EchoInput(cell) + "' is " +
                       (cell.empty()
                            ? "empty; every sample needs a value (remove the row or fill it)"
                            : NotAFiniteNumberReason(cell)));
}

Status ImuLogLineParser::ParseLine(std::string_view line, bool* is_sample) {
  *is_sample = false;
  ++line_number_;
  if (line_number_ < format_.first_data_line) return Status::Ok();
  if (line_number_ == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
  const std::string_view trimmed = TrimLine(line);
  if (trimmed.empty() || trimmed.front() == '#') return Status::Ok();
  double values[4];
  double raw_time = 0.0;
  if (imu_tk_fast_ && ReadFourShortDecimals(trimmed, values)) {
    raw_time = values[0];
    accelerometer_ = {values[1], values[2], values[3]};
  } else {
    SplitImuFields(trimmed, format_.separator, &fields_);
    if (static_cast<int>(fields_.size()) != format_.field_count) {
      return Status::Error(
          StringPrintf("%s: %zu field(s), expected %d (as %s)%s", Where(line_number_).c_str(),
                       fields_.size(), format_.field_count,
                       format_.header.empty()
                           ? StringPrintf("line %lld", format_.first_data_line).c_str()
                           : StringPrintf("the header on line %lld", format_.header_line).c_str(),
                       format_.separator == ' ' && trimmed.find(',') != std::string_view::npos
                           ? "; the rows mix separators: use one (',' or blanks) throughout"
                           : ""));
    }
    static const char* const kAccelerometerRoles[3] = {"ax", "ay", "az"};
    static const char* const kGyroscopeRoles[3] = {"gx", "gy", "gz"};
    if (format_.time_column >= 0) {
      ACCELCAL_RETURN_IF_ERROR(Cell(format_.time_column, "t", &raw_time));
      // A clock in integer ns or us since 1970 has more digits than a double holds: counted
      // from the first sample in integers, exactly.
      const std::string_view cell = fields_[format_.time_column];
      long long integer = 0;
      const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), integer);
      integer_time_ = error == std::errc() && end == cell.data() + cell.size();
      if (integer_time_) integer_time_value_ = integer;
    }
    if (format_.index_column >= 0 && format_.rate_hz > 0.0) {
      ACCELCAL_RETURN_IF_ERROR(Cell(format_.index_column, "sample number", &raw_time));
    } else if (format_.index_column >= 0) {
      // Read only to time host stamps in bursts: a cell that is no number is no refusal here.
      if (!Cell(format_.index_column, "sample number", &sample_number_).ok())
        sample_number_ = std::numeric_limits<double>::quiet_NaN();
    }
    for (int k = 0; k < 3; ++k) {
      if (format_.accelerometer[k] >= 0)
        ACCELCAL_RETURN_IF_ERROR(
            Cell(format_.accelerometer[k], kAccelerometerRoles[k], &accelerometer_[k]));
      if (format_.gyroscope[k] >= 0)
        ACCELCAL_RETURN_IF_ERROR(Cell(format_.gyroscope[k], kGyroscopeRoles[k], &gyroscope_[k]));
    }
  }
  if (format_.rate_hz > 0.0) {
    const double number = format_.index_column >= 0 ? raw_time : static_cast<double>(sample_count_);
    t_s_ = number / format_.rate_hz;
  } else {
    if (sample_count_ == 0 && format_.epoch) {
      time_origin_ = raw_time;
      integer_origin_ = integer_time_;
      integer_time_origin_ = integer_time_value_;
    }
    if (format_.epoch && integer_origin_ && integer_time_) {
      t_s_ = static_cast<double>(integer_time_value_ - integer_time_origin_) * format_.time_scale_s;
    } else {
      t_s_ = (raw_time - time_origin_) * format_.time_scale_s;
    }
  }
  if (!reorder_) ACCELCAL_RETURN_IF_ERROR(CheckTime());
  ++sample_count_;
  *is_sample = true;
  return Status::Ok();
}

Status ImuLogLineParser::CheckTime() {
  if (sample_count_ > 0 && !(t_s_ > previous_t_s_)) {
    return Status::Error(StringPrintf(
        "%s: time %.9g s does not increase from the previous sample's %.9g s; a log's time "
        "must be strictly increasing (sort it, or drop the repeated sample)",
        Where(line_number_).c_str(), t_s_, previous_t_s_));
  }
  previous_t_s_ = t_s_;
  return Status::Ok();
}

void FillSource(const ImuTextFormat& format, ImuLogSource* source) {
  if (source == nullptr) return;
  source->layout = format.description;
  source->notes.clear();
  if (!format.time_rule.empty()) source->notes.push_back(format.time_rule);
  source->notes.insert(source->notes.end(), format.notes.begin(), format.notes.end());
  source->metadata = format.metadata;
  source->accelerometer_unit = format.accelerometer_unit;
  source->gyroscope_unit = format.gyroscope_unit;
  source->time_column.clear();
  if (format.time_column >= 0 && format.rate_hz <= 0.0) {
    source->time_column = format.header.empty()
                              ? "column " + std::to_string(format.time_column + 1)
                              : "'" + EchoInput(format.header[format.time_column]) + "'";
  }
  source->time_scale_s = format.time_scale_s;
  source->times_need_whole_log = format.index_column >= 0 && format.rate_hz > 0.0;
  source->sample_number_column = format.index_column < 0 ? ""
                                 : format.header.empty()
                                     ? "column " + std::to_string(format.index_column + 1)
                                     : "'" + EchoInput(format.header[format.index_column]) + "'";
  source->timing = ImuLogTiming();
  if (format.rate_hz > 0.0) {
    source->timing.from =
        format.index_column >= 0 ? "sample number and --rate_hz" : "row number and --rate_hz";
    source->timing.index_column = source->sample_number_column;
  } else {
    source->timing.from = "time column";
  }
}

// A time axis whose median step is no IMU's, read from a column in a unit stated or inferred:
// the unit that would give an IMU's step, when one does.
Status CheckTimeUnit(const std::vector<double>& timestamp_s, const ImuLogSource& source) {
  if (source.time_column.empty() || timestamp_s.size() < 2) return Status::Ok();
  std::vector<double> steps(timestamp_s.size() - 1);
  for (size_t j = 1; j < timestamp_s.size(); ++j)
    steps[j - 1] = timestamp_s[j] - timestamp_s[j - 1];
  const double step_s = UpperMedian(steps);
  if (!(step_s > 0.0) || (step_s >= kMinRunStepS && step_s <= kMaxRunStepS)) return Status::Ok();
  const double raw_step = step_s / source.time_scale_s;
  const std::vector<int> fitting = PreferUsualRate(raw_step, TimeUnitsForStep(raw_step));
  std::string advice = "give --time_unit=s, ms, us or ns, or --rate_hz=R";
  if (fitting.size() == 1) {
    const char* unit = kTimeUnits[fitting[0]];
    const double candidate_s = raw_step * std::pow(1e-3, fitting[0]);
    advice = StringPrintf("read in %s it steps by %.6g s (%.6g Hz): give --time_unit=%s", unit,
                          candidate_s, 1.0 / candidate_s, unit);
  }
  return Status::Error(StringPrintf(
      "time %s steps by %.6g s as read, %.6g Hz, outside an IMU log's 1 Hz to 100 kHz; %s",
      source.time_column.c_str(), step_s, 1.0 / step_s, advice.c_str()));
}

// What the head's bytes say the file is not: a text log in UTF-8 with '\n' line ends.
Status CheckTextHead(std::string_view head, size_t file_size) {
  if (head.substr(0, 2) == "\xFF\xFE" || head.substr(0, 2) == "\xFE\xFF") {
    return Status::Error(
        "the file is UTF-16 text (it starts with a UTF-16 byte order mark): save or convert it "
        "as UTF-8 (e.g. iconv -f UTF-16 -t UTF-8)");
  }
  if (head.size() >= 4 && head[0] != '\0' && head[1] == '\0' && head[3] == '\0') {
    return Status::Error(
        "the file is UTF-16 text (a NUL after every character, no byte order mark): save or "
        "convert it as UTF-8 (e.g. iconv -f UTF-16LE -t UTF-8)");
  }
  if (head.find('\0') != std::string_view::npos) {
    return Status::Error(
        "the file holds binary data (NUL bytes in its first lines), not a text log nor a MATLAB "
        "v5/v7.3 .mat file; export the log as CSV or text (docs/log-layouts.md)");
  }
  if (head.find('\n') == std::string_view::npos && head.find('\r') != std::string_view::npos &&
      file_size > 0) {
    return Status::Error(
        "the lines end in a carriage return alone (classic Mac line ends), not '\\n': convert "
        "them (e.g. tr '\\r' '\\n' < IN > OUT)");
  }
  return Status::Ok();
}

bool IsMatHeader(std::string_view head) {
  return head.substr(0, 10) == "MATLAB 5.0" || head.substr(0, 10) == "MATLAB 7.3";
}

bool HasMatSuffix(const std::string& path) {
  return path.size() >= 4 && LowerAscii(path.substr(path.size() - 4)) == ".mat";
}

// The file's first kHeadBytes, whether they are all of it, its size, and its identity when they
// were read (the whole reading is checked against it: CheckUnchangedSince).
Status ReadHead(const std::string& path, std::string* head, bool* whole, uint64_t* size,
                FileIdentity* identity) {
  ACCELCAL_RETURN_IF_ERROR(
      CheckInputFile(path, std::numeric_limits<uint64_t>::max(), "an IMU log", size));
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                       &std::fclose);
  if (!file) return Status::Error(std::string("cannot open: ") + std::strerror(errno));
  ACCELCAL_RETURN_IF_ERROR(IdentifyOpenFile(fileno(file.get()), identity));
  head->assign(kHeadBytes, '\0');
  const size_t count = std::fread(head->data(), 1, head->size(), file.get());
  if (count < head->size() && std::ferror(file.get()))
    return Status::Error(std::string("cannot read: ") + std::strerror(errno));
  head->resize(count);
  *whole = count < kHeadBytes || std::fgetc(file.get()) == EOF;
  return Status::Ok();
}

// The file is what it was when its head was read (`before`): the layout was decided from that
// head, and the samples must all come from one state of the file.
Status CheckUnchangedSince(const std::string& path, const FileIdentity& before) {
  FileIdentity now;
  ACCELCAL_RETURN_IF_ERROR(IdentifyFile(path, &now));
  return now == before ? Status::Ok() : FileChangedWhileRead(before, now);
}

// A text log's lines, streamed with the format decided from its head. `sample_numbers`, when
// not null, receives the sample-number column's values when time comes from a time column
// (else it stays empty).
Status StreamTextLog(const std::string& path, const ImuLogReadOptions& options,
                     size_t batch_samples,
                     const std::function<void(const TriadLog& batch)>& on_batch,
                     ImuLogSource* source, bool reorder = false,
                     std::vector<double>* sample_numbers = nullptr) {
  std::string head;
  bool whole = false;
  uint64_t size = 0;
  FileIdentity identity;
  ACCELCAL_RETURN_IF_ERROR(ReadHead(path, &head, &whole, &size, &identity).WithContext(path));
  if (IsMatHeader(head)) {
    return Status::Error(path +
                         ": a MATLAB .mat file is read whole, not streamed; read it with "
                         "calibrate_imu or apply");
  }
  ACCELCAL_RETURN_IF_ERROR(CheckTextHead(head, size).WithContext(path));
  ImuTextFormat format;
  ACCELCAL_RETURN_IF_ERROR(DetectImuTextFormat(head, whole, options, &format).WithContext(path));
  FillSource(format, source);
  ImuLogLineParser parser(format, reorder);
  TriadLog batch;
  const bool gyroscope = format.gyroscope[0] >= 0;
  const bool accelerometer = format.accelerometer[0] >= 0;
  if (format.index_column < 0 || format.rate_hz > 0.0) sample_numbers = nullptr;
  const size_t batch_limit = std::max<size_t>(1, batch_samples);
  ACCELCAL_RETURN_IF_ERROR(StreamTextLines(
      path, "an IMU log", kMaxLineBytes,
      [&](std::string_view line) {
        bool is_sample = false;
        ACCELCAL_RETURN_IF_ERROR(parser.ParseLine(line, &is_sample));
        if (!is_sample) return Status::Ok();
        const std::array<double, 3>& a = parser.accelerometer();
        batch.timestamp_s.push_back(parser.t_s());
        if (accelerometer) batch.output.push_back(a);
        if (gyroscope) batch.gyroscope.push_back(parser.gyroscope());
        if (sample_numbers != nullptr) sample_numbers->push_back(parser.sample_number());
        if (batch.size() >= batch_limit) {
          on_batch(batch);
          batch = TriadLog();
        }
        return Status::Ok();
      },
      [&](std::string_view) { return parser.UnterminatedLastLine(); }));
  ACCELCAL_RETURN_IF_ERROR(CheckUnchangedSince(path, identity).WithContext(path));
  ACCELCAL_RETURN_IF_ERROR(parser.Finish().WithContext(path));
  if (batch.size() > 0) on_batch(batch);
  return Status::Ok();
}

// A .mat variable named in --columns: NAME, NAME(:,K) or NAME[K].
struct VariableColumn {
  std::string name;
  int column = -1;  // from 0; -1: the whole variable
};

bool ParseVariableColumn(const std::string& text, VariableColumn* result) {
  *result = VariableColumn();
  size_t open = text.find_first_of("([");
  if (open == std::string::npos) {
    result->name = text;
    return !text.empty();
  }
  result->name = text.substr(0, open);
  std::string inside = text.substr(open + 1);
  if (inside.empty() || (inside.back() != ')' && inside.back() != ']')) return false;
  inside.pop_back();
  if (inside.rfind(":,", 0) == 0) inside = inside.substr(2);
  if (inside.empty() || inside.size() > 6 || !std::all_of(inside.begin(), inside.end(), [](char c) {
        return std::isdigit(static_cast<unsigned char>(c));
      }))
    return false;
  result->column = std::stoi(inside) - 1;
  return !result->name.empty() && result->column >= 0;
}

// The MAT variables of a log: those read as matrices, and why each other one was not.
struct MatVariables {
  std::vector<std::pair<std::string, MatMatrix>> matrices;
  std::map<std::string, std::string> unread;  // name -> ReadNumericMatrix's refusal
};

// The samples of one MAT variable's column (a vector's only column), as rows.
Status VariableValues(const MatVariables& variables, const VariableColumn& wanted, size_t rows,
                      std::vector<double>* values) {
  const auto& matrices = variables.matrices;
  for (const auto& [name, matrix] : matrices) {
    if (name != wanted.name) continue;
    // Samples along the longer dimension: N x 1 and 1 x N are both vectors.
    const bool by_rows = matrix.rows >= matrix.cols;
    const int length = by_rows ? matrix.rows : matrix.cols;
    const int width = by_rows ? matrix.cols : matrix.rows;
    const int column = wanted.column < 0 ? 0 : wanted.column;
    if (wanted.column < 0 && width != 1) {
      return Status::Error(
          StringPrintf("variable '%s' is %dx%d, not a vector: name one of its "
                       "columns, e.g. %s(:,1)",
                       name.c_str(), matrix.rows, matrix.cols, name.c_str()));
    }
    if (column >= width) {
      return Status::Error(StringPrintf("variable '%s' is %dx%d: it has no column %d", name.c_str(),
                                        matrix.rows, matrix.cols, column + 1));
    }
    if (rows != 0 && static_cast<size_t>(length) != rows) {
      return Status::Error(
          StringPrintf("variable '%s' holds %d samples, the others %zu: the "
                       "variables of a log must be the same length",
                       name.c_str(), length, rows));
    }
    values->resize(length);
    for (int j = 0; j < length; ++j) (*values)[j] = by_rows ? matrix(j, column) : matrix(column, j);
    return Status::Ok();
  }
  const auto unread = variables.unread.find(wanted.name);
  if (unread != variables.unread.end()) return Status::Error(unread->second);
  return Status::Error("no variable '" + EchoInput(wanted.name) + "' in the file");
}

std::string Shape(const MatMatrix& matrix) {
  return std::to_string(matrix.rows) + "x" + std::to_string(matrix.cols);
}

// A struct's field names, "acc, t".
std::string FieldList(const MatVariableDescription& variable) {
  std::string fields;
  for (const std::string& field : variable.fields)
    fields += (fields.empty() ? "" : ", ") + EchoInput(field);
  return fields;
}

// A variable no log reads, as `whos` shows it: "imu (1x1 struct: acc, t)", "name (1x8 char)".
std::string Described(const MatVariableDescription& variable) {
  std::string shape;
  for (uint64_t dimension : variable.dims)
    shape += (shape.empty() ? "" : "x") + std::to_string(dimension);
  return EchoInput(variable.name) + " (" + (shape.empty() ? "" : shape + " ") +
         variable.class_name + (variable.fields.empty() ? "" : ": " + FieldList(variable)) + ")";
}

// A MATLAB .mat log: its variables by name (io/imu_log_format.h's aliases), or by --columns.
// `sample_numbers` as StreamTextLog's.
Status ReadMatLog(const std::string& path, const ImuLogReadOptions& options, TriadLog* log,
                  ImuLogSource* source, std::vector<double>* sample_numbers) {
  std::vector<ImuColumnChoice> choices;
  ACCELCAL_RETURN_IF_ERROR(ParseImuColumnChoices(options.columns, &choices));
  MatFileReader reader;
  ACCELCAL_RETURN_IF_ERROR(reader.Open(path));
  std::vector<MatVariableDescription> described;
  ACCELCAL_RETURN_IF_ERROR(reader.DescribeVariables(&described));
  // Only the numeric variables are read, integers (a logger's raw counts) widened to double; a
  // text or struct variable beside them is left alone, and named with its class.
  MatVariables variables;
  std::vector<std::pair<std::string, MatMatrix>>& matrices = variables.matrices;
  std::string unread_listing;
  for (const MatVariableDescription& variable : described) {
    MatMatrix matrix;
    const Status read = reader.ReadNumericMatrix(variable.name, &matrix);
    if (read.ok()) {
      matrices.emplace_back(variable.name, std::move(matrix));
    } else {
      // A struct's fields are not read: say what it holds, and how to make them variables.
      variables.unread[variable.name] =
          read.message() +
          (variable.fields.empty()
               ? ""
               : " (its fields: " + FieldList(variable) + "); save the fields as variables, e.g. " +
                     EchoInput(variable.fields[0]) + " = " + EchoInput(variable.name) + "." +
                     EchoInput(variable.fields[0]) + "; save('log.mat', '" +
                     EchoInput(variable.fields[0]) + "', ...)");
      unread_listing += (unread_listing.empty() ? "" : ", ") + Described(variable);
    }
  }
  std::string listing;
  for (const auto& [name, matrix] : matrices)
    listing += (listing.empty() ? "" : ", ") + name + " (" + Shape(matrix) + ")";
  if (!unread_listing.empty()) listing += (listing.empty() ? "" : ", ") + unread_listing;
  if (listing.empty()) listing = "none";

  // role -> column of a variable
  std::map<std::string, VariableColumn> chosen;
  for (const ImuColumnChoice& choice : choices) {
    VariableColumn column;
    if (!ParseVariableColumn(choice.value, &column)) {
      return Status::Error("--columns " + choice.key + ":" + EchoInput(choice.value) +
                           ": give a variable, or a column of one as NAME(:,K)");
    }
    if (choice.key == "acc" || choice.key == "gyr") {
      const std::string prefix = choice.key == "acc" ? "a" : "g";
      for (int k = 0; k < 3; ++k) chosen[prefix + "xyz"[k]] = {column.name, k};
    } else {
      chosen[choice.key] = column;
    }
  }
  auto matrix_of = [&](const std::string& name) -> const MatMatrix* {
    for (const auto& entry : matrices) {
      if (entry.first == name) return &entry.second;
    }
    return nullptr;
  };
  // A variable the names would have chosen for a role left empty, but which could not be read:
  // its refusal says more than "no such variable".
  auto unread_for = [&](ImuColumnKind kind) -> const std::string* {
    for (const auto& [name, why] : variables.unread) {
      if (ClassifyImuVariableName(name) == kind || ClassifyImuColumnName(name).kind == kind)
        return &why;
    }
    return nullptr;
  };
  auto long_side = [](const MatMatrix& m) { return std::max(m.rows, m.cols); };
  auto short_side = [](const MatMatrix& m) { return std::min(m.rows, m.cols); };
  // By name: N x 3 triads and vectors per axis, a time vector, a sample number.
  for (const char* prefix : {"a", "g"}) {
    const ImuColumnKind kind =
        prefix[0] == 'a' ? ImuColumnKind::kAccelerometer : ImuColumnKind::kGyroscope;
    if (chosen.count(std::string(prefix) + "x")) continue;
    std::vector<std::string> triads;
    std::array<std::vector<std::string>, 3> axes;
    for (const auto& [name, matrix] : matrices) {
      if (short_side(matrix) == 3 && long_side(matrix) > 3 && ClassifyImuVariableName(name) == kind)
        triads.push_back(name);
      const ImuColumnName column = ClassifyImuColumnName(name);
      if (short_side(matrix) == 1 && column.kind == kind) axes[column.axis].push_back(name);
    }
    if (triads.size() +
                (axes[0].size() == 1 && axes[1].size() == 1 && axes[2].size() == 1 ? 1 : 0) >
            1 ||
        triads.size() > 1) {
      if (kind == ImuColumnKind::kGyroscope) continue;
      return Status::Error("several accelerometers among the variables (" + listing +
                           "): choose one with --columns=acc:NAME (an N x 3 variable) or "
                           "ax:NAME,ay:NAME,az:NAME");
    }
    if (triads.size() == 1) {
      for (int k = 0; k < 3; ++k) chosen[std::string(prefix) + "xyz"[k]] = {triads[0], k};
    } else if (axes[0].size() == 1 && axes[1].size() == 1 && axes[2].size() == 1) {
      for (int k = 0; k < 3; ++k) chosen[std::string(prefix) + "xyz"[k]] = {axes[k][0], -1};
    }
  }
  if (!chosen.count("t")) {
    for (const auto& [name, matrix] : matrices) {
      if (short_side(matrix) == 1 && ClassifyImuColumnName(name).kind == ImuColumnKind::kTime) {
        chosen["t"] = {name, -1};
        break;
      }
    }
  }
  if (!chosen.count("index")) {
    for (const auto& [name, matrix] : matrices) {
      if (short_side(matrix) == 1 &&
          ClassifyImuColumnName(name).kind == ImuColumnKind::kSampleIndex) {
        chosen["index"] = {name, -1};
        break;
      }
    }
  }
  std::vector<std::string> notes;
  // One N x 4 matrix and nothing named: imu_tk's t, x, y, z saved in binary.
  if (!chosen.count("ax") && matrices.size() == 1 && short_side(matrices[0].second) == 4 &&
      choices.empty()) {
    const std::string& name = matrices[0].first;
    chosen["t"] = {name, 0};
    for (int k = 0; k < 3; ++k) chosen[std::string("a") + "xyz"[k]] = {name, k + 1};
    notes.push_back("the file's one variable '" + name + "' (" + Shape(matrices[0].second) +
                    ") read as imu_tk's columns t [s], x, y, z");
  }
  if (options.gyroscope_file) {
    if (!chosen.count("gx") && chosen.count("ax"))
      for (int k = 0; k < 3; ++k)
        chosen[std::string("g") + "xyz"[k]] = chosen[std::string("a") + "xyz"[k]];
    for (int k = 0; k < 3; ++k) chosen.erase(std::string("a") + "xyz"[k]);
    if (!chosen.count("gx")) {
      if (const std::string* why = unread_for(ImuColumnKind::kGyroscope))
        return Status::Error(*why);
      return Status::Error("no gyroscope among the variables (" + listing +
                           "): name it with --columns=gyr:NAME");
    }
  } else if (!chosen.count("ax")) {
    if (const std::string* why = unread_for(ImuColumnKind::kAccelerometer))
      return Status::Error(*why);
    const bool two_axis = matrix_of("Aerr") != nullptr || matrix_of("datos") != nullptr ||
                          matrix_of("theta") != nullptr;
    return Status::Error("no accelerometer among the variables (" + listing +
                         "): name it with --columns=acc:NAME (an N x 3 variable), or "
                         "ax:NAME,ay:NAME,az:NAME, or ax:NAME(:,K),...; with t:NAME for the time" +
                         (two_axis ? std::string("; this looks like the two-axis tilt-table data "
                                                 "(linear_ls, analyze read it)")
                                   : std::string("")));
  }
  // The samples.
  size_t rows = 0;
  std::array<std::vector<double>, 3> accelerometer;
  std::array<std::vector<double>, 3> gyroscope;
  for (int k = 0; k < 3; ++k) {
    const std::string axis(1, "xyz"[k]);
    if (chosen.count("a" + axis)) {
      ACCELCAL_RETURN_IF_ERROR(
          VariableValues(variables, chosen["a" + axis], rows, &accelerometer[k]));
      rows = accelerometer[k].size();
    }
    if (chosen.count("g" + axis)) {
      ACCELCAL_RETURN_IF_ERROR(VariableValues(variables, chosen["g" + axis], rows, &gyroscope[k]));
      rows = gyroscope[k].size();
    }
  }
  std::vector<double> time;
  std::string time_rule;
  double time_scale_s = 1.0;
  if (options.rate_hz > 0.0) {
    std::vector<double> index;
    if (chosen.count("index"))
      ACCELCAL_RETURN_IF_ERROR(VariableValues(variables, chosen["index"], rows, &index));
    time.resize(rows);
    for (size_t j = 0; j < rows; ++j) time[j] = (index.empty() ? j : index[j]) / options.rate_hz;
    time_rule = StringPrintf(
        "time = %s / %g Hz (--rate_hz)",
        index.empty() ? "row number" : ("'" + chosen["index"].name + "'").c_str(), options.rate_hz);
    if (chosen.count("t"))
      notes.push_back("the time variable '" + chosen["t"].name +
                      "' is not used (--rate_hz gives time)");
  } else if (chosen.count("t")) {
    ACCELCAL_RETURN_IF_ERROR(VariableValues(variables, chosen["t"], rows, &time));
    ImuTextFormat format;
    const std::string label = "'" + chosen["t"].name + "'";
    const std::vector<double> head(time.begin(),
                                   time.begin() + std::min<size_t>(time.size(), 2000));
    ACCELCAL_RETURN_IF_ERROR(ChooseTimeUnit(head, label,
                                            ClassifyImuColumnName(chosen["t"].name).time_unit,
                                            options.time_unit, false, &format));
    time_rule = format.time_rule;
    notes.insert(notes.end(), format.notes.begin(), format.notes.end());
    time_scale_s = format.time_scale_s;
    const double origin = format.epoch ? time[0] : 0.0;
    for (double& t : time) t = (t - origin) * format.time_scale_s;
    // Kept to time host stamps in bursts; a variable of another length is of no use for that.
    if (chosen.count("index") &&
        !VariableValues(variables, chosen["index"], rows, sample_numbers).ok())
      sample_numbers->clear();
  } else {
    if (const std::string* why = unread_for(ImuColumnKind::kTime)) return Status::Error(*why);
    return Status::Error("no time variable among (" + listing +
                         "): give --rate_hz=R, the samples' rate in Hz, or name it with "
                         "--columns=t:NAME");
  }
  *log = TriadLog();
  log->timestamp_s = std::move(time);
  for (size_t j = 0; j < rows; ++j) {
    if (!accelerometer[0].empty())
      log->output.push_back({accelerometer[0][j], accelerometer[1][j], accelerometer[2][j]});
    if (!gyroscope[0].empty())
      log->gyroscope.push_back({gyroscope[0][j], gyroscope[1][j], gyroscope[2][j]});
  }
  for (size_t j = 1; j < rows; ++j) {
    if (!(log->timestamp_s[j] > log->timestamp_s[j - 1])) {
      return Status::Error(StringPrintf(
          "sample %zu: time %.9g s does not increase from the previous sample's %.9g s; a log's "
          "time must be strictly increasing",
          j + 1, log->timestamp_s[j], log->timestamp_s[j - 1]));
    }
  }
  if (source != nullptr) {
    auto describe = [&](const char* prefix) {
      const std::string p(prefix);
      if (!chosen.count(p + "x")) return std::string();
      std::string text;
      for (int k = 0; k < 3; ++k) {
        const VariableColumn& c = chosen[p + "xyz"[k]];
        text += (k ? ", " : "") + c.name +
                (c.column < 0 ? "" : "(:," + std::to_string(c.column + 1) + ")");
      }
      return text;
    };
    source->layout = "MATLAB .mat (variables: t = " +
                     (options.rate_hz > 0.0 ? std::string("from --rate_hz") : chosen["t"].name) +
                     (chosen.count("ax") ? "; accelerometer " + describe("a") : std::string()) +
                     (chosen.count("gx") ? "; gyroscope " + describe("g") : std::string()) + ")";
    source->time_column = options.rate_hz > 0.0 ? "" : "'" + chosen["t"].name + "'";
    source->time_scale_s = time_scale_s;
    source->sample_number_column = chosen.count("index") ? "'" + chosen["index"].name + "'" : "";
    source->timing = ImuLogTiming();
    source->timing.from = options.rate_hz <= 0.0  ? "time column"
                          : chosen.count("index") ? "sample number and --rate_hz"
                                                  : "row number and --rate_hz";
    if (options.rate_hz > 0.0) source->timing.index_column = source->sample_number_column;
    source->notes.clear();
    if (!time_rule.empty()) source->notes.push_back(time_rule);
    source->notes.insert(source->notes.end(), notes.begin(), notes.end());
    source->metadata.clear();
  }
  return Status::Ok();
}

// Rows whose time is their sample number over the rate, listed out of order (imucal's
// annotated session lists its sections by label), put back in the order they were recorded;
// a sample number twice is refused.
Status OrderBySampleNumber(TriadLog* log, ImuLogSource* source) {
  const std::vector<double>& t = log->timestamp_s;
  if (std::is_sorted(t.begin(), t.end())) {
    for (size_t j = 1; j < t.size(); ++j) {
      if (t[j] == t[j - 1]) {
        return Status::Error(
            StringPrintf("samples %zu and %zu have one sample number (t = %.9g s): "
                         "each row must be its own sample",
                         j, j + 1, t[j]));
      }
    }
    return Status::Ok();
  }
  std::vector<size_t> order(t.size());
  for (size_t j = 0; j < order.size(); ++j) order[j] = j;
  std::stable_sort(order.begin(), order.end(), [&t](size_t a, size_t b) { return t[a] < t[b]; });
  size_t runs = 1;
  for (size_t j = 1; j < t.size(); ++j) runs += t[j] < t[j - 1] ? 1 : 0;
  TriadLog sorted;
  for (size_t j : order) {
    sorted.timestamp_s.push_back(t[j]);
    if (!log->output.empty()) sorted.output.push_back(log->output[j]);
    if (!log->gyroscope.empty()) sorted.gyroscope.push_back(log->gyroscope[j]);
  }
  for (size_t j = 1; j < sorted.size(); ++j) {
    if (sorted.timestamp_s[j] == sorted.timestamp_s[j - 1]) {
      return Status::Error(StringPrintf(
          "two rows have the sample number of t = %.9g s: each row must be its own sample",
          sorted.timestamp_s[j]));
    }
  }
  *log = std::move(sorted);
  if (source != nullptr) {
    source->notes.push_back(StringPrintf(
        "rows put in the order of their sample numbers (the file lists them out of order, in %zu "
        "ascending runs, as imucal's annotated session lists its sections by label)",
        runs));
  }
  return Status::Ok();
}

// A ROS 2 bag (io/ros2_bag.h): its layout defines the columns, units and time, so the flags
// that say them for a text or .mat log are refused rather than ignored.
Status ReadBagLog(const std::string& path, const ImuLogReadOptions& options, TriadLog* log,
                  ImuLogSource* source) {
  const char* flag = !options.columns.empty()          ? "--columns"
                     : options.rate_hz > 0.0           ? "--rate_hz"
                     : !options.time_unit.empty()      ? "--time_unit"
                     : !options.gyroscope_path.empty() ? "--gyro_log"
                     : options.gyroscope_file          ? "--gyro_log"
                                                       : nullptr;
  if (flag != nullptr) {
    return Status::Error(path + ": " + flag +
                         " is for text and .mat logs; a ROS 2 bag's sensor_msgs/msg/Imu "
                         "messages name their fields, units and time (choose the topic with "
                         "--topic, the time with --bag_time)");
  }
  Ros2BagReadOptions bag_options;
  bag_options.topic = options.topic;
  if (!ParseRos2BagTime(options.bag_time, &bag_options.time)) {
    return Status::Error("--bag_time='" + EchoInput(options.bag_time) +
                         "' is not a time of a bag's messages; use header or receive");
  }
  Ros2BagSource bag;
  ACCELCAL_RETURN_IF_ERROR(ReadRos2BagImuLog(path, bag_options, log, &bag));
  if (source != nullptr) {
    *source = ImuLogSource();
    source->layout = bag.layout;
    source->notes = bag.notes;
    source->accelerometer_unit = "m/s^2";  // REP 145
    source->gyroscope_unit = "rad/s";
    source->units_stated_by = "sensor_msgs/msg/Imu (REP 145) says";
  }
  return Status::Ok();
}

// --topic and --bag_time given for a log that is no bag.
Status RefuseBagOptions(const std::string& path, const ImuLogReadOptions& options) {
  if (options.topic.empty() && options.bag_time == "header") return Status::Ok();
  return Status::Error(path +
                       ": --topic and --bag_time are for ROS 2 bags (a folder with "
                       "metadata.yaml, or a .db3 file); this log is not one");
}

// The whole of one file, of any layout, without the spacing check. `sample_numbers` as
// StreamTextLog's (may be null).
Status ReadOneFile(const std::string& path, const ImuLogReadOptions& options, TriadLog* log,
                   ImuLogSource* source, std::vector<double>* sample_numbers) {
  *log = TriadLog();
  std::vector<double> unused;
  if (sample_numbers == nullptr) sample_numbers = &unused;
  sample_numbers->clear();
  if (IsRos2Bag(path)) return ReadBagLog(path, options, log, source);
  ACCELCAL_RETURN_IF_ERROR(RefuseBagOptions(path, options));
  std::string head;
  bool whole = false;
  uint64_t size = 0;
  FileIdentity identity;
  ACCELCAL_RETURN_IF_ERROR(ReadHead(path, &head, &whole, &size, &identity).WithContext(path));
  // A MAT file by its header (v5, v7.3), or a binary .mat without one (v4). matio reads it by
  // its path: the file must be unchanged from the head to the end of the reading, and a run's
  // record of its bytes (io/input_file.h) is their checksum taken in the same state.
  if (IsMatHeader(head) || (head.find('\0') != std::string::npos && HasMatSuffix(path))) {
    ACCELCAL_RETURN_IF_ERROR(
        ReadMatLog(path, options, log, source, sample_numbers).WithContext(path));
    ACCELCAL_RETURN_IF_ERROR(CheckUnchangedSince(path, identity).WithContext(path));
    if (!RecordingInputReads()) return Status::Ok();
    InputRead read;
    ACCELCAL_RETURN_IF_ERROR(HashFile(path, &read).WithContext(path));
    if (read.identity != identity)
      return FileChangedWhileRead(identity, read.identity).WithContext(path);
    return RecordInputRead(path, read).WithContext(path);
  }
  ACCELCAL_RETURN_IF_ERROR(StreamTextLog(
      path, options, 1 << 16,
      [log](const TriadLog& batch) {
        log->timestamp_s.insert(log->timestamp_s.end(), batch.timestamp_s.begin(),
                                batch.timestamp_s.end());
        log->output.insert(log->output.end(), batch.output.begin(), batch.output.end());
        log->gyroscope.insert(log->gyroscope.end(), batch.gyroscope.begin(), batch.gyroscope.end());
      },
      source, /*reorder=*/true, sample_numbers));
  return OrderBySampleNumber(log, source).WithContext(path);
}

// imu_tk's pair: the gyroscope's file must carry the accelerometer's time stamps.
Status AddPairedGyroscope(const std::string& path, const ImuLogReadOptions& options, TriadLog* log,
                          ImuLogSource* source) {
  if (log->has_gyroscope()) {
    return Status::Error(
        "--gyro_log: the log already has gyroscope columns; give the gyroscope "
        "once, in the log or in its own file");
  }
  ImuLogReadOptions gyroscope_options = options;
  gyroscope_options.gyroscope_path.clear();
  gyroscope_options.gyroscope_file = true;
  gyroscope_options.columns.clear();
  TriadLog gyroscope;
  ImuLogSource gyroscope_source;
  ACCELCAL_RETURN_IF_ERROR(
      ReadOneFile(path, gyroscope_options, &gyroscope, &gyroscope_source, nullptr));
  if (gyroscope.size() != log->size()) {
    return Status::Error(StringPrintf(
        "%s: %zu samples, the accelerometer's log %zu: imu_tk's pair of files must hold the same "
        "time stamps, one row each",
        path.c_str(), gyroscope.size(), log->size()));
  }
  for (size_t j = 0; j < log->size(); ++j) {
    const double a = log->timestamp_s[j];
    const double g = gyroscope.timestamp_s[j];
    if (std::abs(a - g) > 1e-9 * std::max(1.0, std::abs(a))) {
      return Status::Error(StringPrintf(
          "%s: sample %zu is at t = %.9g s, the accelerometer's at %.9g s: imu_tk's pair of files "
          "must hold the same time stamps",
          path.c_str(), j + 1, g, a));
    }
  }
  log->gyroscope = std::move(gyroscope.gyroscope);
  if (source != nullptr) {
    source->gyroscope_path = path;
    source->gyroscope_unit = gyroscope_source.gyroscope_unit;
    source->notes.push_back("gyroscope: " + path + ", " + gyroscope_source.layout +
                            ", the same time stamps");
  }
  return Status::Ok();
}

// A time column of host stamps in bursts, and nothing to time the samples by: what the
// stamps look like and the flag that times them.
Status RefuseHostTimeBursts(bool bag, const ImuLogReadOptions& options, const ImuLogSource& source,
                            const HostTimeBursts& bursts) {
  const std::string statistics = DescribeHostTimeBursts(bursts);
  if (bag) {
    const bool receive = options.bag_time == "receive";
    return Status::Error(
        std::string("the messages' ") + (receive ? "receive times" : "header stamps") +
        " come in bursts (" + statistics +
        "): a host's stamps of buffered samples, not the "
        "samples' times; " +
        (receive ? "read the driver's stamps with --bag_time=header"
                 : "an Imu message carries no sample number to time it by: have the driver "
                   "stamp each sample with the device's time"));
  }
  return Status::Error(StringPrintf(
      "time %s: the time stamps come in bursts (%s): a host's receive times of buffered "
      "samples, not the samples' times; give --rate_hz=%.6g, the mean rate, to time the samples "
      "by their order, or --columns=index:NAME naming a column that counts the samples (their "
      "times then come from it at a rate fitted to these stamps)",
      source.time_column.c_str(), statistics.c_str(), bursts.mean_rate_hz()));
}

// The sample numbers' jumps beyond 1, from times that are sample numbers over `rate_hz`.
long long DroppedSamples(const std::vector<double>& timestamp_s, double rate_hz) {
  long long dropped = 0;
  for (size_t j = 1; j < timestamp_s.size(); ++j)
    dropped += std::llround((timestamp_s[j] - timestamp_s[j - 1]) * rate_hz) - 1;
  return dropped;
}

// The samples' times once the log is read (ImuLogTiming): a time column of host stamps in
// bursts is replaced by the sample numbers' times at a fitted rate, or refused; sample numbers
// over --rate_hz count the samples they skip.
Status TimeTheSamples(bool bag, const ImuLogReadOptions& options,
                      const std::vector<double>& sample_numbers, TriadLog* log,
                      ImuLogSource* source) {
  ImuLogTiming& timing = source->timing;
  if (options.rate_hz > 0.0) {
    if (timing.index_column.empty()) return Status::Ok();
    timing.dropped_samples = DroppedSamples(log->timestamp_s, options.rate_hz);
    if (timing.dropped_samples > 0) {
      source->notes.push_back(StringPrintf(
          "%lld dropped sample%s: the sample numbers in %s skip them; the samples read keep their "
          "numbers' times",
          timing.dropped_samples, timing.dropped_samples == 1 ? "" : "s",
          timing.index_column.c_str()));
    }
    return Status::Ok();
  }
  const HostTimeBursts bursts = MeasureHostTimeBursts(log->timestamp_s);
  if (!bursts.bursty) return Status::Ok();
  if (sample_numbers.empty()) return RefuseHostTimeBursts(bag, options, *source, bursts);
  std::vector<double> timestamp_s;
  ACCELCAL_RETURN_IF_ERROR(
      FitIndexClock(sample_numbers, log->timestamp_s, &timing.fit, &timestamp_s)
          .WithContext("time " + source->time_column + " comes in bursts, timed by " +
                       source->sample_number_column));
  log->timestamp_s = std::move(timestamp_s);
  timing.from = "sample number and a fitted rate";
  timing.index_column = source->sample_number_column;
  timing.bursts = bursts;
  timing.rate_fitted = true;
  timing.dropped_samples = timing.fit.dropped_samples;
  source->notes.insert(source->notes.begin(),
                       "time: host receive times in bursts in " + source->time_column + " (" +
                           DescribeHostTimeBursts(bursts) + "): sample times from the index " +
                           timing.index_column + " " + DescribeIndexClockFit(timing.fit));
  return Status::Ok();
}

}  // namespace

Status ParseImuLog(std::string_view text, const ImuLogReadOptions& options, TriadLog* log,
                   ImuLogSpacing spacing, ImuLogSource* source) {
  *log = TriadLog();
  ACCELCAL_RETURN_IF_ERROR(CheckTextHead(text.substr(0, kHeadBytes), text.size()));
  const std::string_view head = text.substr(0, kHeadBytes);
  ImuTextFormat format;
  ACCELCAL_RETURN_IF_ERROR(DetectImuTextFormat(head, head.size() == text.size(), options, &format));
  FillSource(format, source);
  ImuLogLineParser parser(format, false);
  const bool sample_numbers_kept = format.index_column >= 0 && format.rate_hz <= 0.0;
  std::vector<double> sample_numbers;
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) return parser.UnterminatedLastLine();
    bool is_sample = false;
    ACCELCAL_RETURN_IF_ERROR(parser.ParseLine(text.substr(begin, end - begin), &is_sample));
    if (is_sample) {
      log->timestamp_s.push_back(parser.t_s());
      if (format.accelerometer[0] >= 0) log->output.push_back(parser.accelerometer());
      if (format.gyroscope[0] >= 0) log->gyroscope.push_back(parser.gyroscope());
      if (sample_numbers_kept) sample_numbers.push_back(parser.sample_number());
    }
    begin = end + 1;
  }
  ACCELCAL_RETURN_IF_ERROR(parser.Finish());
  ImuLogSource read;
  FillSource(format, &read);
  ACCELCAL_RETURN_IF_ERROR(TimeTheSamples(false, options, sample_numbers, log, &read));
  ACCELCAL_RETURN_IF_ERROR(CheckTimeUnit(log->timestamp_s, read));
  if (source != nullptr) *source = read;
  return CheckSpacing(log->timestamp_s, spacing);
}

Status StreamImuLog(const std::string& path, const ImuLogReadOptions& options, size_t batch_samples,
                    const std::function<void(const TriadLog& batch)>& on_batch,
                    ImuLogSource* source) {
  if (!options.gyroscope_path.empty()) {
    return Status::Error("--gyro_log: a pair of files is read whole; this reader streams one file");
  }
  if (IsRos2Bag(path)) {  // read whole (SQLite's own paging), then handed over in batches
    TriadLog whole;
    ACCELCAL_RETURN_IF_ERROR(ReadBagLog(path, options, &whole, source));
    for (size_t first = 0; first < whole.size(); first += std::max<size_t>(batch_samples, 1)) {
      const size_t last = std::min(whole.size(), first + std::max<size_t>(batch_samples, 1));
      TriadLog batch;
      batch.timestamp_s.assign(whole.timestamp_s.begin() + first, whole.timestamp_s.begin() + last);
      batch.output.assign(whole.output.begin() + first, whole.output.begin() + last);
      batch.gyroscope.assign(whole.gyroscope.begin() + first, whole.gyroscope.begin() + last);
      on_batch(batch);
    }
    return Status::Ok();
  }
  ACCELCAL_RETURN_IF_ERROR(RefuseBagOptions(path, options));
  ImuLogSource local;
  if (source == nullptr) source = &local;
  HostTimeBurstTally tally;
  ACCELCAL_RETURN_IF_ERROR(StreamTextLog(
      path, options, batch_samples,
      [&](const TriadLog& batch) {
        for (double t_s : batch.timestamp_s) tally.Add(t_s);
        on_batch(batch);
      },
      source));
  // As ReadImuLog's TimeTheSamples decides, from the same statistics.
  const HostTimeBursts bursts = tally.Result();
  if (options.rate_hz > 0.0 || !bursts.bursty) return Status::Ok();
  if (source->sample_number_column.empty())
    return RefuseHostTimeBursts(false, options, *source, bursts).WithContext(path);
  source->times_need_whole_log = true;
  return Status::Error(path + ": time " + source->time_column +
                       " holds host stamps in bursts, timed by " + source->sample_number_column +
                       " at a rate fitted to the whole log: read it whole");
}

bool StreamsLikeReadImuLog(const std::string& path, const ImuLogReadOptions& options) {
  if (!options.gyroscope_path.empty()) return false;
  std::string head;
  bool whole = false;
  uint64_t size = 0;
  FileIdentity identity;
  if (!ReadHead(path, &head, &whole, &size, &identity).ok()) return false;
  return !IsMatHeader(head) && head.find('\0') == std::string::npos;
}

Status ReadImuLog(const std::string& path, const ImuLogReadOptions& options, TriadLog* log,
                  ImuLogSpacing spacing, ImuLogSource* source) {
  ImuLogSource local;
  if (source == nullptr) source = &local;
  std::vector<double> sample_numbers;
  ACCELCAL_RETURN_IF_ERROR(ReadOneFile(path, options, log, source, &sample_numbers));
  if (!options.gyroscope_path.empty())
    ACCELCAL_RETURN_IF_ERROR(AddPairedGyroscope(options.gyroscope_path, options, log, source));
  // Bursts first: their median step is the within-burst one, which says nothing of the unit.
  ACCELCAL_RETURN_IF_ERROR(
      TimeTheSamples(IsRos2Bag(path), options, sample_numbers, log, source).WithContext(path));
  ACCELCAL_RETURN_IF_ERROR(CheckTimeUnit(log->timestamp_s, *source).WithContext(path));
  return CheckSpacing(log->timestamp_s, spacing).WithContext(path);
}

Status ReadImuLog(const std::string& path, TriadLog* log, ImuLogSpacing spacing) {
  return ReadImuLog(path, ImuLogReadOptions(), log, spacing, nullptr);
}

}  // namespace accelcal
