#include "io/imu_log_format.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <ctime>
#include <map>
#include <set>

#include "common/format.h"
#include "common/statistics.h"
#include "io/course_data.h"
#include "io/csv_reader.h"
#include "io/input_text.h"

namespace accelcal {
namespace {

constexpr int kRowsToAgree = 5;           // a data block: this many rows alike (or all there are)
constexpr size_t kMaxMetadataLines = 50;  // echoed before the header, at most
constexpr size_t kMaxMetadataChars = 120;
constexpr double kEpochMinS = 1e8;          // a time axis beyond 3 years is a clock's epoch
constexpr double kTypicalRateLowHz = 20.0;  // of two plausible units, the one in this band
constexpr double kTypicalRateHighHz = 2000.0;

std::string_view TrimCell(std::string_view text) {
  auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  if (text.size() >= 2 && text.front() == '"' && text.back() == '"') {
    text.remove_prefix(1);
    text.remove_suffix(1);
  }
  return text;
}

bool IsAxisToken(const std::string& token, int* axis) {
  if (token.size() != 1) return false;
  const char c = token[0];
  if (c < 'x' || c > 'z') return false;
  *axis = c - 'x';
  return true;
}

std::string WithoutTrailingDigits(const std::string& token) {
  size_t end = token.size();
  while (end > 0 && std::isdigit(static_cast<unsigned char>(token[end - 1]))) --end;
  return token.substr(0, end);
}

const std::set<std::string>& AccelerometerWords() {
  static const std::set<std::string> words = {"a",
                                              "acc",
                                              "accel",
                                              "accl",
                                              "accelerometer",
                                              "acceleration",
                                              "accelerations",
                                              "accelero",
                                              "specificforce",
                                              "alpha",
                                              "beschleunigung"};
  return words;
}
const std::set<std::string>& GyroscopeWords() {
  static const std::set<std::string> words = {"g",      "gyr",     "gyro",     "gyroscope",
                                              "gyros",  "w",       "omega",    "angular",
                                              "angvel", "angrate", "gyrometer"};
  return words;
}
const std::set<std::string>& TimeWords() {
  static const std::set<std::string> words = {
      "t",       "time",    "timestamp", "timestamps", "stamp", "ts",     "sec",   "secs",
      "seconds", "elapsed", "timems",    "times",      "zeit",  "millis", "micros"};
  return words;
}
const std::set<std::string>& IndexWords() {
  static const std::set<std::string> words = {
      "sample", "samples", "index", "idx", "counter", "seq", "nsamples", "samplenumber", "frame"};
  return words;
}
// Units a name may end in ("acc_x_g", "gyr_x_dps", "t_ms"), by what they measure.
const std::map<std::string, std::string>& TimeUnitWords() {
  static const std::map<std::string, std::string> words = {
      {"s", "s"},   {"sec", "s"},   {"ms", "ms"},   {"us", "us"},
      {"ns", "ns"}, {"msec", "ms"}, {"usec", "us"}, {"nsec", "ns"}};
  return words;
}
const std::map<std::string, std::string>& ValueUnitWords() {
  static const std::map<std::string, std::string> words = {
      {"g", "g"},         {"mps2", "m/s^2"},   {"ms2", "m/s^2"},   {"mg", "mg"},
      {"rads", "rad/s"},  {"rad", "rad/s"},    {"dps", "deg/s"},   {"degs", "deg/s"},
      {"radps", "rad/s"}, {"degps", "deg/s"},  {"deg", "deg/s"},   {"lsb", "count"},
      {"raw", "count"},   {"counts", "count"}, {"count", "count"}, {"si", ""}};
  return words;
}

// A unit written in brackets: "[ns]", "(m/s^2)", "[m s^-2]", "[rad s^-1]", "(deg/s)".
std::string BracketUnit(const std::string& text) {
  std::string compact;
  for (char c : LowerAscii(text)) {
    if (c != ' ' && c != '*' && c != '.') compact += c;
  }
  static const std::map<std::string, std::string> units = {{"s", "s"},
                                                           {"sec", "s"},
                                                           {"ms", "ms"},
                                                           {"us", "us"},
                                                           {"\xc2\xb5s", "us"},
                                                           {"ns", "ns"},
                                                           {"m/s^2", "m/s^2"},
                                                           {"m/s2", "m/s^2"},
                                                           {"ms^-2", "m/s^2"},
                                                           {"ms-2", "m/s^2"},
                                                           {"m/s/s", "m/s^2"},
                                                           {"g", "g"},
                                                           {"rad/s", "rad/s"},
                                                           {"rads^-1", "rad/s"},
                                                           {"rads-1", "rad/s"},
                                                           {"deg/s", "deg/s"},
                                                           {"dps", "deg/s"},
                                                           {"\xc2\xb0/s", "deg/s"},
                                                           {"mg", "mg"},
                                                           {"lsb", "count"},
                                                           {"counts", "count"},
                                                           {"count", "count"},
                                                           {"m/s\xc2\xb2", "m/s^2"},
                                                           {"ms\xe2\x81\xbb\xc2\xb2", "m/s^2"}};
  const auto found = units.find(compact);
  return found == units.end() ? "" : found->second;
}

// The name's words: brackets taken out (their unit returned apart), split at every character
// that is not a letter or digit and where a lower-case letter meets an upper-case one
// ("AccX" -> acc, x), lower-cased.
std::vector<std::string> NameTokens(std::string_view name, std::string* bracket_unit) {
  std::string rest;
  bracket_unit->clear();
  for (size_t i = 0; i < name.size(); ++i) {
    const char open = name[i];
    if (open == '[' || open == '(') {
      const char close = open == '[' ? ']' : ')';
      const size_t end = name.find(close, i + 1);
      if (end != std::string_view::npos) {
        const std::string unit = BracketUnit(std::string(name.substr(i + 1, end - i - 1)));
        if (!unit.empty()) *bracket_unit = unit;
        i = end;
        rest += ' ';
        continue;
      }
    }
    rest += name[i];
  }
  std::vector<std::string> tokens;
  std::string token;
  auto flush = [&] {
    if (!token.empty()) tokens.push_back(LowerAscii(token));
    token.clear();
  };
  for (size_t i = 0; i < rest.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(rest[i]);
    if (!std::isalnum(c)) {
      flush();
      continue;
    }
    if (!token.empty() && std::isupper(c) &&
        std::islower(static_cast<unsigned char>(token.back()))) {
      flush();
    }
    token += static_cast<char>(c);
  }
  flush();
  return tokens;
}

// "accx" -> acc + x, "gx" -> g + x: a family word and an axis letter written as one word.
bool SplitFamilyAxis(const std::string& token, const std::set<std::string>& family, int* axis) {
  if (token.size() < 2) return false;
  const std::string stem = WithoutTrailingDigits(token.substr(0, token.size() - 1));
  return IsAxisToken(token.substr(token.size() - 1), axis) && family.count(stem) > 0;
}

std::string JoinTokens(const std::vector<std::string>& tokens) {
  std::string joined;
  for (const std::string& token : tokens) joined += (joined.empty() ? "" : "_") + token;
  return joined;
}

bool ParseCell(std::string_view cell, bool decimal_comma, double* value) {
  if (!decimal_comma) return ParseFiniteNumber(cell, value);
  std::string copy(cell);
  std::replace(copy.begin(), copy.end(), ',', '.');
  return ParseFiniteNumber(copy, value);
}

bool MostlyNumbers(const std::vector<std::string_view>& fields, bool decimal_comma) {
  int numbers = 0;
  double value = 0.0;
  for (std::string_view field : fields) numbers += ParseCell(field, decimal_comma, &value) ? 1 : 0;
  return numbers >= 2 && 2 * numbers >= static_cast<int>(fields.size());
}

bool AnyText(const std::vector<std::string_view>& fields) {
  double value = 0.0;
  for (std::string_view field : fields) {
    if (!field.empty() && !ParseFiniteNumber(field, &value)) return true;
  }
  return false;
}

std::string SeparatorName(char separator) {
  switch (separator) {
    case ',':
      return "CSV";
    case ';':
      return "';'-separated";
    case '\t':
      return "tab-separated";
    case '|':
      return "'|'-separated";
    default:
      return "whitespace-separated";
  }
}

struct HeadLine {
  long long number = 0;
  std::string_view text;
};

bool IsSkipped(std::string_view line) {
  const std::string_view trimmed = TrimLine(line);
  return trimmed.empty() || trimmed.front() == '#';
}

std::string Quoted(const std::string& name) { return "'" + EchoInput(name) + "'"; }

std::string ColumnLabel(const ImuTextFormat& format, int column) {
  if (!format.header.empty()) return Quoted(format.header[column]);
  return "column " + std::to_string(column + 1);
}

std::string UtcDate(double epoch_s) {
  // A date only for a time a clock can hold (1970 to the year 5000), not any large number.
  if (!(epoch_s >= 0.0 && epoch_s < 1e11)) return "";
  const std::time_t seconds = static_cast<std::time_t>(std::floor(epoch_s));
  std::tm utc{};
  if (gmtime_r(&seconds, &utc) == nullptr) return "";
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S UTC", &utc);
  return text;
}

// A --columns value in a text log: a header name (exact, then ignoring case), or a number.
Status ResolveColumn(const ImuTextFormat& format, const ImuColumnChoice& choice, int* column) {
  for (size_t c = 0; c < format.header.size(); ++c) {
    if (format.header[c] == choice.value) {
      *column = static_cast<int>(c);
      return Status::Ok();
    }
  }
  int matches = 0;
  for (size_t c = 0; c < format.header.size(); ++c) {
    if (LowerAscii(format.header[c]) == LowerAscii(choice.value)) {
      *column = static_cast<int>(c);
      ++matches;
    }
  }
  if (matches == 1) return Status::Ok();
  const bool digits =
      !choice.value.empty() && std::all_of(choice.value.begin(), choice.value.end(), [](char c) {
        return std::isdigit(static_cast<unsigned char>(c));
      });
  if (digits && choice.value.size() < 7) {
    const int number = std::stoi(choice.value);
    if (number >= 1 && number <= format.field_count) {
      *column = number - 1;
      return Status::Ok();
    }
    return Status::Error(StringPrintf("--columns %s:%s: the rows have %d columns (1 to %d)",
                                      choice.key.c_str(), choice.value.c_str(), format.field_count,
                                      format.field_count));
  }
  std::string names;
  for (const std::string& name : format.header)
    names += (names.empty() ? "" : ", ") + EchoInput(name);
  return Status::Error(
      "--columns " + choice.key + ":" + EchoInput(choice.value) + ": no column has that name" +
      (format.header.empty() ? std::string(" (the log has no header: give a column number from 1)")
                             : " (the header names: " + names + ")"));
}

// One device's columns of a kind: axis -> column, with every column seen for an axis.
struct DeviceColumns {
  std::string device;
  std::array<std::vector<int>, 3> axes;
  bool Complete() const {
    return axes[0].size() == 1 && axes[1].size() == 1 && axes[2].size() == 1;
  }
  std::array<int, 3> Columns() const { return {axes[0][0], axes[1][0], axes[2][0]}; }
};

std::vector<DeviceColumns> Devices(const std::vector<ImuColumnName>& names, ImuColumnKind kind) {
  std::vector<DeviceColumns> devices;
  for (size_t c = 0; c < names.size(); ++c) {
    if (names[c].kind != kind) continue;
    auto it = std::find_if(devices.begin(), devices.end(),
                           [&](const DeviceColumns& d) { return d.device == names[c].device; });
    if (it == devices.end()) {
      devices.push_back({names[c].device, {}});
      it = devices.end() - 1;
    }
    it->axes[names[c].axis].push_back(static_cast<int>(c));
  }
  return devices;
}

std::string TripleNames(const ImuTextFormat& format, const std::array<int, 3>& columns) {
  return ColumnLabel(format, columns[0]) + ", " + ColumnLabel(format, columns[1]) + ", " +
         ColumnLabel(format, columns[2]);
}

std::string ColumnsFlag(const ImuTextFormat& format, const char* prefix,
                        const std::array<int, 3>& columns) {
  std::string flag;
  for (int k = 0; k < 3; ++k) {
    flag += std::string(k == 0 ? "" : ",") + prefix + "xyz"[k] + ":" +
            (format.header.empty() ? std::to_string(columns[k] + 1) : format.header[columns[k]]);
  }
  return flag;
}

// The accelerometer or gyroscope by name, when --columns did not give it.
Status ChooseTriadByName(const std::vector<ImuColumnName>& names, ImuColumnKind kind,
                         const std::string& preferred_device, ImuTextFormat* format,
                         std::array<int, 3>* columns) {
  const bool accelerometer = kind == ImuColumnKind::kAccelerometer;
  const char* what = accelerometer ? "accelerometer" : "gyroscope";
  const char* prefix = accelerometer ? "a" : "g";
  std::vector<DeviceColumns> complete;
  std::vector<DeviceColumns> partial;
  for (const DeviceColumns& device : Devices(names, kind)) {
    (device.Complete() ? complete : partial).push_back(device);
  }
  if (complete.size() > 1 && !preferred_device.empty()) {
    for (const DeviceColumns& device : complete) {
      if (device.device != preferred_device) continue;
      *columns = device.Columns();
      format->notes.push_back(StringPrintf(
          "%s: %s, of the same device as the accelerometer ('%s'), among %zu gyroscopes", what,
          TripleNames(*format, *columns).c_str(), EchoInput(preferred_device).c_str(),
          complete.size()));
      return Status::Ok();
    }
  }
  if (complete.size() == 1) {
    *columns = complete[0].Columns();
    return Status::Ok();
  }
  if (complete.size() > 1) {
    std::string list;
    for (const DeviceColumns& device : complete)
      list += (list.empty() ? "" : "; ") + TripleNames(*format, device.Columns());
    if (!accelerometer) {
      format->notes.push_back(StringPrintf(
          "gyroscope: not read: %zu gyroscopes in the file (%s); choose one with --columns=%s",
          complete.size(), list.c_str(),
          ColumnsFlag(*format, prefix, complete[0].Columns()).c_str()));
      return Status::Ok();
    }
    return Status::Error(StringPrintf(
        "the file holds %zu accelerometers (%s), and a log is calibrated one sensor at a time: "
        "choose one with --columns=%s (and each of the others in a run of its own)",
        complete.size(), list.c_str(),
        ColumnsFlag(*format, prefix, complete[0].Columns()).c_str()));
  }
  if (!accelerometer) return Status::Ok();  // no gyroscope: nothing to read
  // No named accelerometer: bare x, y, z columns are the sensor's.
  std::array<int, 3> bare{-1, -1, -1};
  int bare_count = 0;
  for (size_t c = 0; c < format->header.size(); ++c) {
    int axis = -1;
    if (IsAxisToken(LowerAscii(std::string(TrimCell(format->header[c]))), &axis) &&
        bare[axis] < 0) {
      bare[axis] = static_cast<int>(c);
      ++bare_count;
    }
  }
  if (bare_count == 3) {
    *columns = bare;
    format->notes.push_back(
        "accelerometer: the columns x, y, z (the header names no sensor; this is the --log, the "
        "accelerometer's)");
    return Status::Ok();
  }
  std::string header;
  for (const std::string& name : format->header)
    header += (header.empty() ? "" : ", ") + EchoInput(name);
  std::string partial_text;
  if (!partial.empty()) {
    partial_text = " (the columns";
    for (const auto& axis : partial[0].axes) {
      for (int c : axis) partial_text += " " + Quoted(format->header[c]);
    }
    partial_text += " name an accelerometer, but not exactly one column per axis x, y, z)";
  }
  return Status::Error("line " + std::to_string(format->header_line) +
                       ": no accelerometer columns in the header (" + header + ")" + partial_text +
                       "; name them with --columns=ax:NAME,ay:NAME,az:NAME (docs/log-layouts.md)");
}

Status ChooseColumns(const std::vector<ImuColumnChoice>& choices, const ImuLogReadOptions& options,
                     ImuTextFormat* format) {
  std::vector<ImuColumnName> names;
  for (const std::string& name : format->header) names.push_back(ClassifyImuColumnName(name));
  bool accelerometer_given = false;
  bool gyroscope_given = false;
  std::array<bool, 3> accelerometer_keys{};
  std::array<bool, 3> gyroscope_keys{};
  for (const ImuColumnChoice& choice : choices) {
    if (choice.key == "acc" || choice.key == "gyr") {
      return Status::Error("--columns " + choice.key +
                           ": takes an N x 3 variable of a .mat file; in a text log name the "
                           "columns one by one (" +
                           (choice.key == "acc" ? "ax, ay, az" : "gx, gy, gz") + ")");
    }
    int column = -1;
    ACCELCAL_RETURN_IF_ERROR(ResolveColumn(*format, choice, &column));
    if (choice.key == "t") {
      format->time_column = column;
    } else if (choice.key == "index") {
      format->index_column = column;
    } else if (choice.key[0] == 'a') {
      format->accelerometer[choice.key[1] - 'x'] = column;
      accelerometer_keys[choice.key[1] - 'x'] = true;
      accelerometer_given = true;
    } else {
      format->gyroscope[choice.key[1] - 'x'] = column;
      gyroscope_keys[choice.key[1] - 'x'] = true;
      gyroscope_given = true;
    }
  }
  if (accelerometer_given &&
      !(accelerometer_keys[0] && accelerometer_keys[1] && accelerometer_keys[2]))
    return Status::Error(
        "--columns: give the accelerometer's three columns together (ax, ay and az)");
  if (gyroscope_given && !(gyroscope_keys[0] && gyroscope_keys[1] && gyroscope_keys[2]))
    return Status::Error("--columns: give the gyroscope's three columns together (gx, gy and gz)");

  if (format->header.empty()) {
    // No names: imu_tk's layout, or the columns the user numbered.
    if (!accelerometer_given) {
      if (format->field_count == 4) {
        if (format->time_column < 0 && options.rate_hz <= 0.0) format->time_column = 0;
        format->accelerometer = {1, 2, 3};
      } else if (format->field_count == 3 && options.rate_hz > 0.0) {
        format->accelerometer = {0, 1, 2};
      } else if (format->field_count == 3) {
        return Status::Error(StringPrintf(
            "line %lld: 3 numbers per row, no header and no time: give --rate_hz=R, the rows' "
            "rate in Hz (the columns are then read as x, y, z)",
            format->first_data_line));
      } else {
        return Status::Error(StringPrintf(
            "line %lld: %d numbers per row and no header naming them; name the columns, e.g. "
            "--columns=t:1,ax:2,ay:3,az:4 (numbers from 1; docs/log-layouts.md)",
            format->first_data_line, format->field_count));
      }
    }
  } else {
    std::string device;
    const bool named_gyroscope =
        std::any_of(names.begin(), names.end(),
                    [](const ImuColumnName& n) { return n.kind == ImuColumnKind::kGyroscope; });
    if (!accelerometer_given && !(options.gyroscope_file && named_gyroscope)) {
      ACCELCAL_RETURN_IF_ERROR(ChooseTriadByName(names, ImuColumnKind::kAccelerometer, "", format,
                                                 &format->accelerometer));
    }
    if (format->accelerometer[0] >= 0 &&
        names[format->accelerometer[0]].kind == ImuColumnKind::kAccelerometer)
      device = names[format->accelerometer[0]].device;
    if (!gyroscope_given) {
      ACCELCAL_RETURN_IF_ERROR(
          ChooseTriadByName(names, ImuColumnKind::kGyroscope, device, format, &format->gyroscope));
    }
    std::vector<int> times;
    std::vector<int> indices;
    for (size_t c = 0; c < names.size(); ++c) {
      if (names[c].kind == ImuColumnKind::kTime) times.push_back(static_cast<int>(c));
      if (names[c].kind == ImuColumnKind::kSampleIndex) indices.push_back(static_cast<int>(c));
    }
    if (format->time_column < 0 && !times.empty()) {
      int chosen = times[0];
      int stated = 0;
      for (int c : times) stated += names[c].time_unit.empty() ? 0 : 1;
      if (stated == 1) {
        for (int c : times) {
          if (!names[c].time_unit.empty()) chosen = c;
        }
      }
      format->time_column = chosen;
      if (times.size() > 1) {
        std::string others;
        for (int c : times) {
          if (c != chosen) others += (others.empty() ? "" : ", ") + Quoted(format->header[c]);
        }
        format->notes.push_back("time: " + Quoted(format->header[chosen]) + " (" +
                                (stated == 1 ? "the one time column whose name states its unit"
                                             : "the first time column") +
                                "; not " + others + "; choose with --columns=t:NAME)");
      }
    }
    if (format->index_column < 0 && !indices.empty()) format->index_column = indices[0];
    const auto unit_of = [&](const std::array<int, 3>& columns) {
      return columns[0] >= 0 ? names[columns[0]].value_unit : std::string();
    };
    format->accelerometer_unit = unit_of(format->accelerometer);
    format->gyroscope_unit = unit_of(format->gyroscope);
  }
  // The gyroscope's file of a pair: its triad, named or not, is the gyroscope.
  if (options.gyroscope_file) {
    if (format->gyroscope[0] < 0) format->gyroscope = format->accelerometer;
    format->accelerometer = {-1, -1, -1};
    if (format->gyroscope[0] < 0)
      return Status::Error(
          "no gyroscope columns: name them with --columns=gx:NAME,gy:NAME,gz:NAME");
  }
  // A column may serve one role.
  std::vector<int> used;
  for (int c : format->accelerometer) used.push_back(c);
  for (int c : format->gyroscope) used.push_back(c);
  used.push_back(format->time_column);
  std::vector<int> seen;
  for (int c : used) {
    if (c < 0) continue;
    if (std::find(seen.begin(), seen.end(), c) != seen.end()) {
      return Status::Error("--columns: " + ColumnLabel(*format, c) +
                           " is given two roles; each column is one of t, ax, ay, az, gx, gy, gz");
    }
    seen.push_back(c);
  }
  return Status::Ok();
}

// The head's values of one column, from its data rows.
std::vector<double> HeadColumn(const std::vector<HeadLine>& lines, const ImuTextFormat& format,
                               int column) {
  std::vector<double> values;
  std::vector<std::string_view> fields;
  for (const HeadLine& line : lines) {
    if (line.number < format.first_data_line || IsSkipped(line.text)) continue;
    SplitImuFields(line.text, format.separator, &fields);
    double value = 0.0;
    if (static_cast<int>(fields.size()) != format.field_count ||
        !ParseCell(fields[column], format.decimal_comma, &value))
      break;
    values.push_back(value);
  }
  return values;
}

Status ChooseTime(const std::vector<HeadLine>& lines, const ImuLogReadOptions& options,
                  bool imu_tk_layout, ImuTextFormat* format) {
  if (options.rate_hz > 0.0) {
    format->rate_hz = options.rate_hz;
    if (format->index_column >= 0) {
      format->time_rule =
          StringPrintf("time = (sample number in %s) / %g Hz (--rate_hz)",
                       ColumnLabel(*format, format->index_column).c_str(), options.rate_hz);
    } else {
      format->time_rule = StringPrintf("time = row number / %g Hz (--rate_hz)", options.rate_hz);
    }
    if (format->time_column >= 0) {
      format->notes.push_back("the time column " + ColumnLabel(*format, format->time_column) +
                              " is not used (--rate_hz gives time)");
      format->time_column = -1;
    }
    return Status::Ok();
  }
  if (format->time_column < 0) {
    if (format->index_column >= 0) {
      return Status::Error("no time column; " + ColumnLabel(*format, format->index_column) +
                           " numbers the samples: give --rate_hz=R, the rate they were recorded "
                           "at in Hz (e.g. imucal's example: --rate_hz=204.8)");
    }
    return Status::Error(
        "no time column (none named t, time, timestamp, ...): give --rate_hz=R, the rows' rate in "
        "Hz, or name the time column with --columns=t:NAME");
  }
  const std::string label = ColumnLabel(*format, format->time_column);
  const std::vector<double> head_times = HeadColumn(lines, *format, format->time_column);
  const std::string named_unit =
      format->header.empty() ? ""
                             : ClassifyImuColumnName(format->header[format->time_column]).time_unit;
  return ChooseTimeUnit(head_times, label, named_unit, options.time_unit, imu_tk_layout, format);
}

}  // namespace

bool TimeUnitToSeconds(std::string_view unit, double* seconds) {
  if (unit == "s") {
    *seconds = 1.0;
  } else if (unit == "ms") {
    *seconds = 1e-3;
  } else if (unit == "us") {
    *seconds = 1e-6;
  } else if (unit == "ns") {
    *seconds = 1e-9;
  } else if (unit == "100us") {  // Xsens's SampleTimeFine
    *seconds = 1e-4;
  } else {
    return false;
  }
  return true;
}

ImuColumnName ClassifyImuColumnName(std::string_view name) {
  ImuColumnName result;
  std::string bracket_unit;
  std::vector<std::string> tokens = NameTokens(TrimCell(name), &bracket_unit);
  // "%time" (rostopic), "field.header.stamp": the generic words carry nothing.
  if (tokens.empty()) return result;
  // Units at the end: "acc_x_g", "t_ms", "gyr_x_dps" (not the name's only word).
  std::string name_unit;
  while (tokens.size() > 1) {
    int axis = -1;
    const std::string& last = tokens.back();
    if (IsAxisToken(last, &axis)) break;
    if (TimeUnitWords().count(last)) {
      name_unit = TimeUnitWords().at(last);
    } else if (ValueUnitWords().count(last)) {
      name_unit = ValueUnitWords().at(last);
    } else if (last == "2" || last == "s2" || last == "m") {
      // "m_s2", "m_s_2": a unit spelled in words
      name_unit = "m/s^2";
    } else {
      break;
    }
    tokens.pop_back();
  }
  if (!bracket_unit.empty()) name_unit = bracket_unit;
  const bool time_unit =
      name_unit == "s" || name_unit == "ms" || name_unit == "us" || name_unit == "ns";

  // Xsens's SampleTimeFine counts ticks of 100 us; its PacketCounter counts samples.
  if (tokens == std::vector<std::string>{"sample", "time", "fine"}) {
    result.kind = ImuColumnKind::kTime;
    result.time_unit = "100us";
    return result;
  }
  if (tokens == std::vector<std::string>{"packet", "counter"}) {
    result.kind = ImuColumnKind::kSampleIndex;
    return result;
  }
  // Time and sample number: a time word and nothing of an axis.
  int axis = -1;
  bool has_axis = false;
  for (const std::string& token : tokens) has_axis = has_axis || IsAxisToken(token, &axis);
  if (!has_axis) {
    for (const std::string& token : tokens) {
      if (TimeWords().count(token)) {
        result.kind = ImuColumnKind::kTime;
        if (time_unit) result.time_unit = name_unit;
        if (token == "timems" || token == "millis") result.time_unit = "ms";
        if (token == "micros") result.time_unit = "us";
        return result;
      }
    }
    for (const std::string& token : tokens) {
      if (IndexWords().count(token) || (token == "n" && tokens.size() == 1)) {
        result.kind = ImuColumnKind::kSampleIndex;
        return result;
      }
    }
  }
  // A triad's axis: a family word and an axis, separate ("acc_x") or joined ("accx", "ax").
  std::vector<std::string> rest;
  ImuColumnKind kind = ImuColumnKind::kOther;
  int found_axis = -1;
  for (size_t i = 0; i < tokens.size(); ++i) {
    const std::string& token = tokens[i];
    const std::string stem = WithoutTrailingDigits(token);
    int joined_axis = -1;
    if (kind == ImuColumnKind::kOther && AccelerometerWords().count(stem)) {
      kind = ImuColumnKind::kAccelerometer;
      if (stem != token) rest.push_back(token.substr(stem.size()));
    } else if (kind == ImuColumnKind::kOther && GyroscopeWords().count(stem)) {
      kind = ImuColumnKind::kGyroscope;
      if (stem != token) rest.push_back(token.substr(stem.size()));
    } else if (kind == ImuColumnKind::kOther && found_axis < 0 &&
               SplitFamilyAxis(token, AccelerometerWords(), &joined_axis)) {
      kind = ImuColumnKind::kAccelerometer;
      found_axis = joined_axis;
    } else if (kind == ImuColumnKind::kOther && found_axis < 0 &&
               SplitFamilyAxis(token, GyroscopeWords(), &joined_axis)) {
      kind = ImuColumnKind::kGyroscope;
      found_axis = joined_axis;
    } else if (found_axis < 0 && IsAxisToken(token, &joined_axis)) {
      found_axis = joined_axis;
    } else if (token == "velocity" || token == "rate" || token == "linear" || token == "field" ||
               token == "data" || token == "raw" || token == "meas") {
      // "angular_velocity", "linear_acceleration", rostopic's "field.": part of the family
      // word or nothing; "raw" outputs are what is calibrated
      continue;
    } else {
      rest.push_back(token);
    }
  }
  if (kind == ImuColumnKind::kOther || found_axis < 0) return result;
  // Magnetometers and gravity estimates share axis names: a family word must be there.
  result.kind = kind;
  result.axis = found_axis;
  result.device = JoinTokens(rest);
  if (!time_unit) result.value_unit = name_unit;
  return result;
}

ImuColumnKind ClassifyImuVariableName(std::string_view name) {
  const ImuColumnName column = ClassifyImuColumnName(name);
  if (column.kind != ImuColumnKind::kOther) return column.kind;
  std::string bracket_unit;
  for (const std::string& token : NameTokens(TrimCell(name), &bracket_unit)) {
    const std::string stem = WithoutTrailingDigits(token);
    if (AccelerometerWords().count(stem)) return ImuColumnKind::kAccelerometer;
    if (GyroscopeWords().count(stem)) return ImuColumnKind::kGyroscope;
  }
  return ImuColumnKind::kOther;
}

Status ParseImuColumnChoices(const std::string& text, std::vector<ImuColumnChoice>* choices) {
  choices->clear();
  if (text.empty()) return Status::Ok();
  static const std::set<std::string> kKeys = {"t",  "index", "ax", "ay",  "az",
                                              "gx", "gy",    "gz", "acc", "gyr"};
  // Split at commas outside parentheses: "ax:acc(:,1)".
  std::vector<std::string> items;
  std::string item;
  int depth = 0;
  for (char c : text) {
    if (c == '(') ++depth;
    if (c == ')') depth = std::max(0, depth - 1);
    if (c == ',' && depth == 0) {
      items.push_back(item);
      item.clear();
    } else {
      item += c;
    }
  }
  items.push_back(item);
  for (const std::string& entry : items) {
    const size_t colon = entry.find(':');
    const std::string key = colon == std::string::npos ? entry : entry.substr(0, colon);
    const std::string value = colon == std::string::npos ? "" : entry.substr(colon + 1);
    if (!kKeys.count(key)) {
      return Status::Error("--columns: '" + EchoInput(key) +
                           "' is not a key; use t, index, ax, ay, az, gx, gy, gz (and acc, gyr "
                           "for a .mat file's N x 3 variables), as KEY:NAME, e.g. "
                           "--columns=t:time,ax:ACC_X,ay:ACC_Y,az:ACC_Z");
    }
    if (value.empty()) {
      return Status::Error("--columns: " + key +
                           " has no column; give KEY:NAME (a header name or a column number "
                           "from 1), e.g. " +
                           key + ":" + (key == "t" ? "time" : key));
    }
    for (const ImuColumnChoice& earlier : *choices) {
      if (earlier.key == key) return Status::Error("--columns: " + key + " is given twice");
    }
    choices->push_back({key, value});
  }
  return Status::Ok();
}

void SplitImuFields(std::string_view line, char separator, std::vector<std::string_view>* fields) {
  fields->clear();
  if (separator == ' ') {
    const char* p = line.data();
    const char* const end = p + line.size();
    auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
    while (p < end) {
      while (p < end && blank(*p)) ++p;
      if (p == end) break;
      const char* const field = p;
      while (p < end && !blank(*p)) ++p;
      fields->push_back(TrimCell(std::string_view(field, p - field)));
    }
    return;
  }
  size_t begin = 0;
  while (true) {
    const size_t end = line.find(separator, begin);
    fields->push_back(TrimCell(
        line.substr(begin, end == std::string_view::npos ? std::string_view::npos : end - begin)));
    if (end == std::string_view::npos) break;
    begin = end + 1;
  }
}

std::string_view TrimLine(std::string_view text) {
  auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

Status CutShortLine(long long line_number) {
  return Status::Error("line " + std::to_string(line_number) +
                       " has no line end: the file looks cut short; copy it again, or end the "
                       "line if it is complete");
}

std::vector<int> TimeUnitsForStep(double raw_step) {
  std::vector<int> units;
  for (int u = 0; u < 4; ++u) {
    const double step_s = raw_step * std::pow(1e-3, u);
    if (step_s >= kMinRunStepS && step_s <= kMaxRunStepS) units.push_back(u);
  }
  return units;
}

std::vector<int> PreferUsualRate(double raw_step, const std::vector<int>& units) {
  if (units.size() != 2) return units;
  std::vector<int> usual;
  for (const int u : units) {
    const double rate_hz = 1.0 / (raw_step * std::pow(1e-3, u));
    if (rate_hz >= kTypicalRateLowHz && rate_hz <= kTypicalRateHighHz) usual.push_back(u);
  }
  return usual.size() == 1 ? usual : units;
}

namespace {

// Time values that count 0, 1, 2, ... (or from any small integer) by 1, a sample dropped or
// not: whole numbers whose median step is 1. A sample number far more often than a time.
bool CountsByOne(const std::vector<double>& head_times) {
  if (head_times.size() < 2 || !(std::abs(head_times.front()) < 1e6)) return false;
  std::vector<double> steps;
  for (size_t j = 0; j < head_times.size(); ++j) {
    if (head_times[j] != std::floor(head_times[j])) return false;
    if (j > 0) steps.push_back(head_times[j] - head_times[j - 1]);
  }
  return UpperMedian(steps) == 1.0;
}

// The refusal of a time that counts by 1; `name_says_seconds`: its column's name says seconds,
// which a flag must confirm.
Status SampleNumberAsTime(const std::string& column, bool name_says_seconds) {
  return Status::Error(
      "time " + column + " counts 0, 1, 2, ... by 1: " +
      (name_says_seconds ? "its name says seconds, but 1 Hz is no IMU's usual rate and this "
                           "looks like a sample number"
                         : "a sample number, not a time") +
      "; give --rate_hz=R, the rows' rate in Hz (or --time_unit=s, ms, us or ns if it is a " +
      "time" + (name_says_seconds ? ": --time_unit=s reads a 1 Hz log)" : ")"));
}

}  // namespace

Status InferTimeUnit(const std::vector<double>& head_times, const std::string& column,
                     bool seconds_by_layout, ImuTextFormat* format) {
  if (head_times.size() < 2 || !(head_times.back() > head_times.front())) {
    format->time_scale_s = 1.0;  // the reader's own checks will say what is wrong with time
    format->time_rule = "";
    return Status::Ok();
  }
  // The mean step: host stamps of buffered packets bunch (a median of 1 ms in a 50 Hz log).
  const double step = (head_times.back() - head_times.front()) / (head_times.size() - 1);
  if (CountsByOne(head_times)) return SampleNumberAsTime(column, false);
  std::vector<int> plausible = TimeUnitsForStep(step);
  // A clock's epoch says its unit by its size (s, ms, us or ns since 1970: 1e9 .. 4e9 s).
  const double first = std::abs(head_times.front());
  for (const int u : plausible) {
    const double scale = std::pow(1e-3, u);
    if (first * scale >= 1e9 && first * scale <= 4e9) {
      format->time_scale_s = scale;
      format->time_rule = StringPrintf(
          "time %s in %s: a Unix time in %s by its size (inferred; --time_unit states it), "
          "%.6g Hz",
          column.c_str(), kTimeUnits[u], kTimeUnits[u], 1.0 / (step * scale));
      return Status::Ok();
    }
  }
  // imu_tk's layout is in seconds by definition: no word when seconds fit.
  if (seconds_by_layout && !plausible.empty() && plausible[0] == 0) {
    format->time_scale_s = 1.0;
    format->time_rule = "";
    return Status::Ok();
  }
  plausible = PreferUsualRate(step, plausible);
  if (plausible.size() != 1) {
    std::string options;
    for (int u : plausible) {
      options += StringPrintf("%s%s (%.6g Hz)", options.empty() ? "" : " or ", kTimeUnits[u],
                              1.0 / (step * std::pow(1e-3, u)));
    }
    return Status::Error(StringPrintf(
        "time %s steps by %.6g, a rate no IMU unit makes unambiguous%s%s: give --time_unit=s, "
        "ms, us or ns, or --rate_hz=R",
        column.c_str(), step, options.empty() ? "" : ": ", options.c_str()));
  }
  const int u = plausible[0];
  format->time_scale_s = std::pow(1e-3, u);
  format->time_rule = StringPrintf(
      "time %s in %s, inferred from its median step %.6g (%.6g Hz; --time_unit states it)",
      column.c_str(), kTimeUnits[u], step, 1.0 / (step * format->time_scale_s));
  return Status::Ok();
}

Status ChooseTimeUnit(const std::vector<double>& head_times, const std::string& label,
                      const std::string& named_unit, const std::string& flag_unit,
                      bool seconds_by_layout, ImuTextFormat* format) {
  if (!flag_unit.empty()) {
    if (!TimeUnitToSeconds(flag_unit, &format->time_scale_s))
      return Status::Error("--time_unit='" + EchoInput(flag_unit) +
                           "' is not a unit; use s, ms, us or ns");
    format->time_rule = "time " + label + " in " + flag_unit + " (--time_unit)";
  } else if (!named_unit.empty()) {
    if (named_unit == "s" && CountsByOne(head_times)) return SampleNumberAsTime(label, true);
    TimeUnitToSeconds(named_unit, &format->time_scale_s);
    format->time_rule =
        named_unit == "s" ? "" : "time " + label + " in " + named_unit + " (its name says so)";
  } else {
    ACCELCAL_RETURN_IF_ERROR(InferTimeUnit(head_times, label, seconds_by_layout, format));
  }
  if (!head_times.empty() && std::abs(head_times.front() * format->time_scale_s) >= kEpochMinS) {
    format->epoch = true;
    const double start_s = head_times.front() * format->time_scale_s;
    const std::string date = UtcDate(start_s);
    format->notes.push_back(
        StringPrintf("time: %s starts at %.17g s%s%s; times here are from the first sample",
                     label.c_str(), start_s, date.empty() ? "" : ", Unix time ", date.c_str()));
  }
  return Status::Ok();
}

Status DetectImuTextFormat(std::string_view head, bool whole, const ImuLogReadOptions& options,
                           ImuTextFormat* format) {
  *format = ImuTextFormat();
  std::vector<ImuColumnChoice> choices;
  ACCELCAL_RETURN_IF_ERROR(ParseImuColumnChoices(options.columns, &choices));
  if (head.substr(0, 3) == "\xEF\xBB\xBF") head.remove_prefix(3);
  // The head's lines; a last line without '\n' only when the head is the whole file.
  // The head's complete lines: a last line without '\n' is left to the reader, which refuses
  // a file cut short.
  std::vector<HeadLine> lines;
  size_t begin = 0;
  bool cut_short = false;
  while (begin < head.size()) {
    const size_t end = head.find('\n', begin);
    if (end == std::string_view::npos) {
      cut_short = whole;
      break;
    }
    lines.push_back({static_cast<long long>(lines.size() + 1), head.substr(begin, end - begin)});
    begin = end + 1;
  }
  // The first data row: kRowsToAgree rows (or all there are) alike under one separator.
  static const char kSeparators[] = {',', ';', '\t', '|', ' '};
  std::vector<std::string_view> fields;
  std::vector<std::string_view> next_fields;
  size_t data = lines.size();
  for (size_t i = 0; i < lines.size() && data == lines.size(); ++i) {
    if (IsSkipped(lines[i].text)) continue;
    for (char separator : kSeparators) {
      SplitImuFields(TrimLine(lines[i].text), separator, &fields);
      if (fields.size() < 2) continue;
      bool decimal_comma = false;
      if (!MostlyNumbers(fields, false)) {
        if (separator != ';' || !MostlyNumbers(fields, true)) continue;
        decimal_comma = true;
      }
      int agreeing = 1;
      bool differs = false;
      for (size_t j = i + 1; j < lines.size() && agreeing < kRowsToAgree; ++j) {
        if (IsSkipped(lines[j].text)) continue;
        SplitImuFields(TrimLine(lines[j].text), separator, &next_fields);
        if (next_fields.size() != fields.size() || !MostlyNumbers(next_fields, decimal_comma)) {
          differs = true;
          break;
        }
        ++agreeing;
      }
      if (differs) continue;
      data = i;
      format->separator = separator;
      format->decimal_comma = decimal_comma;
      format->field_count = static_cast<int>(fields.size());
      format->first_data_line = lines[i].number;
      break;
    }
  }
  if (data == lines.size()) {
    if (cut_short) {
      return CutShortLine(static_cast<long long>(lines.size()) + 1);
    }
    if (std::all_of(lines.begin(), lines.end(),
                    [](const HeadLine& l) { return IsSkipped(l.text); }))
      return Status::Error("no samples: the file holds no rows, only comments or blank lines");
    return Status::Error(StringPrintf(
        "no rows of numbers in the first %zu lines: expected rows of the same number of "
        "fields (2 or more, most of them numbers), separated by ',', ';', tabs or blanks, "
        "after at most a header and a few lines of metadata (docs/log-layouts.md)",
        lines.size()));
  }
  // The header: of the (at most two) lines just above the data that split as the data do and
  // hold text, the one whose names give an accelerometer (a units row may sit under the names).
  // Rows that end in a separator (a trailing ',') have an empty last field the header lacks.
  bool rows_end_empty = true;
  for (size_t i = data, rows = 0; i < lines.size() && rows < kRowsToAgree; ++i) {
    if (IsSkipped(lines[i].text)) continue;
    SplitImuFields(TrimLine(lines[i].text), format->separator, &next_fields);
    rows_end_empty = rows_end_empty && !next_fields.empty() && next_fields.back().empty();
    ++rows;
  }
  std::vector<size_t> candidates;
  for (size_t i = data; i-- > 0 && candidates.size() < 2;) {
    std::string_view text = TrimLine(lines[i].text);
    if (text.empty()) continue;
    if (text.front() == '#') text.remove_prefix(1);
    SplitImuFields(text, format->separator, &fields);
    const bool trailing_separator =
        static_cast<int>(fields.size()) == format->field_count - 1 && rows_end_empty;
    if ((static_cast<int>(fields.size()) != format->field_count && !trailing_separator) ||
        !AnyText(fields))
      break;
    candidates.push_back(i);
  }
  size_t header = lines.size();
  for (size_t i : candidates) {
    std::string_view text = TrimLine(lines[i].text);
    if (text.front() == '#') text.remove_prefix(1);
    SplitImuFields(text, format->separator, &fields);
    bool names_a_sensor = false;
    for (std::string_view field : fields) {
      const ImuColumnKind kind = ClassifyImuColumnName(field).kind;
      names_a_sensor =
          names_a_sensor || kind == ImuColumnKind::kAccelerometer || kind == ImuColumnKind::kTime;
    }
    if (header == lines.size() || names_a_sensor) {
      header = i;
      if (names_a_sensor) break;
    }
  }
  if (header != lines.size()) {
    std::string_view text = TrimLine(lines[header].text);
    if (text.front() == '#') text.remove_prefix(1);
    SplitImuFields(text, format->separator, &fields);
    for (std::string_view field : fields) format->header.emplace_back(field);
    if (static_cast<int>(format->header.size()) == format->field_count - 1) {
      format->header.emplace_back("");
      format->notes.push_back(
          "every row ends in a separator the header does not: its empty last field is ignored");
    }
    format->header_line = lines[header].number;
    for (size_t i = header + 1; i < data; ++i) {
      if (!TrimLine(lines[i].text).empty())
        format->notes.push_back("line " + std::to_string(lines[i].number) +
                                ", between the header and the data, is skipped (a units row?): '" +
                                EchoInput(TrimLine(lines[i].text)) + "'");
    }
  }
  const size_t metadata_end = header != lines.size() ? header : data;
  for (size_t i = 0; i < metadata_end; ++i) {
    const std::string_view text = TrimLine(lines[i].text);
    if (text.empty()) continue;
    if (format->metadata.size() == kMaxMetadataLines) break;
    // Kept as written when printable (a report shows it), else quoted as messages quote.
    const std::string line(text.substr(0, kMaxMetadataChars));
    format->metadata.push_back(IsPrintableUtf8(line) ? line : EchoInput(line));
  }

  ACCELCAL_RETURN_IF_ERROR(ChooseColumns(choices, options, format));
  const bool imu_tk_layout = format->header.empty() && format->separator == ' ' &&
                             format->field_count == 4 && choices.empty();
  ACCELCAL_RETURN_IF_ERROR(ChooseTime(lines, options, imu_tk_layout, format));
  if (!format->metadata.empty()) {
    format->notes.insert(
        format->notes.begin(),
        StringPrintf("%zu line(s) before the %s are metadata, skipped (first: '%s')",
                     format->metadata.size(), format->header.empty() ? "data" : "header",
                     format->metadata.front().c_str()));
  }
  if (format->decimal_comma) format->notes.push_back("numbers with a decimal comma (9,81)");

  // The description: the two layouts of earlier versions keep their names.
  const bool legacy_csv =
      format->separator == ',' &&
      format->header == std::vector<std::string>{"t_s", "acc_x", "acc_y", "acc_z"};
  if (imu_tk_layout && format->time_rule.empty() && !format->epoch) {
    format->description = "whitespace ASCII (t [s], x, y, z)";
  } else if (legacy_csv && format->time_rule.empty() && format->metadata.empty()) {
    format->description = "CSV (t_s,acc_x,acc_y,acc_z)";
  } else {
    std::string text = SeparatorName(format->separator);
    text += format->header.empty() ? " (no header"
                                   : " (header on line " + std::to_string(format->header_line);
    if (format->time_column >= 0) text += "; t = " + ColumnLabel(*format, format->time_column);
    if (format->accelerometer[0] >= 0)
      text += "; accelerometer " + TripleNames(*format, format->accelerometer);
    if (format->gyroscope[0] >= 0) text += "; gyroscope " + TripleNames(*format, format->gyroscope);
    format->description = text + ")";
  }
  return Status::Ok();
}

}  // namespace accelcal
