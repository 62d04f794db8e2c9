#include "io/provenance.h"

#include <cctype>
#include <ctime>
#include <vector>

#include "common/format.h"
#include "common/line_text.h"
#include "common/sha256.h"
#include "io/input_file.h"

#ifndef ACCELCAL_VERSION
#error "ACCELCAL_VERSION must be defined by the build (src/CMakeLists.txt)"
#endif

namespace accelcal {
namespace {

std::string& RecordedCommandLine() {
  static std::string command_line;
  return command_line;
}

// An argument with a line break or another control character (or bytes that are not UTF-8) in
// bash's $'...' quoting, where each is a backslash escape: the command line stays one line
// wherever it is written (a CSV's '#' line, a YAML comment), and bash reads it back as the
// same word. EscapeForLine's escapes are $'...''s, with the backslash and the quote escaped too.
std::string DollarQuotedWord(const std::string& argument) {
  std::string quoted = "$'";
  for (const char c : argument) {
    if (c == '\\' || c == '\'') {
      quoted += '\\';
      quoted += c;
    } else {
      quoted += c;
    }
  }
  // EscapeForLine leaves backslashes as they are, so the ones escaped above stay escapes of a
  // backslash, and each of its own (\n, \xNN, \u2028 ...) is the escape bash reads back.
  return EscapeForLine(quoted) + "'";
}

// An argument as a POSIX shell would need it to read it back as one word.
std::string ShellWord(const std::string& argument) {
  if (argument.empty()) return "''";
  if (NeedsLineEscape(argument)) return DollarQuotedWord(argument);
  bool plain = true;
  for (const char c : argument) {
    const bool safe = std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ||
                      c == '=' || c == '.' || c == '/' || c == ',' || c == ':' || c == '+' ||
                      c == '@' || c == '%';
    plain = plain && safe;
  }
  if (plain) return argument;
  std::string quoted = "'";
  for (const char c : argument) {
    quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  }
  return quoted + "'";
}

}  // namespace

const char* AccelcalVersion() { return ACCELCAL_VERSION; }

std::string UtcNow(const char* format) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[64];
  return std::strftime(text, sizeof(text), format, &utc) > 0 ? text : "";
}

Status HashInputFile(const std::string& path, InputFile* file) {
  // Any size: the file is read in pieces, never whole.
  constexpr uint64_t kNoCap = ~uint64_t{0};
  uint64_t size = 0;
  ACCELCAL_RETURN_IF_ERROR(CheckInputFile(path, kNoCap, "an input file", &size).WithContext(path));
  InputRead read;
  if (FindInputRead(path, &read)) {
    // The bytes the run parsed, while the file is still what was parsed.
    FileIdentity now;
    ACCELCAL_RETURN_IF_ERROR(IdentifyFile(path, &now).WithContext(path));
    if (now != read.identity) {
      return Status::Error(
          path + StringPrintf(": the file changed after it was read (%llu bytes read, %llu now): a "
                              "logger may still be writing it; copy it once the recording has "
                              "stopped and give the copy",
                              static_cast<unsigned long long>(read.bytes),
                              static_cast<unsigned long long>(now.size)));
    }
  } else {
    ACCELCAL_RETURN_IF_ERROR(HashFile(path, &read).WithContext(path));
    ACCELCAL_RETURN_IF_ERROR(RecordInputRead(path, read).WithContext(path));
  }
  file->path = path;
  file->bytes = read.bytes;
  file->sha256 = read.sha256;
  return Status::Ok();
}

Status DescribeMeasuredData(const std::string& data_dir,
                            const std::map<std::string, std::string>& files, DataSource* source) {
  DataSource described;
  described.data_dir = data_dir;
  for (const auto& [role, path] : files) {
    if (path.empty()) continue;
    std::vector<InputFolderPart> parts;
    if (FindInputFolder(path, &parts)) {
      for (const InputFolderPart& part : parts)
        ACCELCAL_RETURN_IF_ERROR(
            HashInputFile(part.path, &described.files[role + part.role_suffix]));
      continue;
    }
    ACCELCAL_RETURN_IF_ERROR(HashInputFile(path, &described.files[role]));
  }
  *source = std::move(described);
  return Status::Ok();
}

namespace {

// The first line, its paths as they are.
std::string DataLineText(const DataSource& source) {
  if (source.simulated) {
    std::string line = "data: simulated, scenario " + source.scenario;
    const auto scenario_file = source.files.find("scenario");
    if (scenario_file != source.files.end()) line += " (" + scenario_file->second.path + ")";
    line += ", seed " + std::to_string(source.seed);
    if (source.hidden.empty()) return line + ", nothing hidden beyond the baseline";
    for (size_t i = 0; i < source.hidden.size(); ++i) {
      line += (i == 0 ? ", hidden " : ", ") + source.hidden[i].first + "=" +
              RoundTripDouble(source.hidden[i].second);
    }
    return line;
  }
  const size_t count = source.files.size();
  const std::string files = std::to_string(count) + (count == 1 ? " file" : " files");
  if (!source.data_dir.empty()) return "data: " + source.data_dir + " (" + files + ")";
  std::string line = "data: ";
  bool first = true;
  for (const auto& [role, file] : source.files) {
    line += (first ? "" : ", ") + file.path;
    first = false;
  }
  return line;
}

}  // namespace

std::string DataLine(const DataSource& source) {
  // One line whatever the paths hold (common/line_text.h).
  return EscapeForLine(DataLineText(source));
}

nlohmann::json InputFilesJson(const std::map<std::string, InputFile>& files) {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& [role, file] : files) {
    json[role] = {{"path", file.path}, {"bytes", file.bytes}, {"sha256", file.sha256}};
  }
  return json;
}

void AddProvenanceJson(const DataSource& source, nlohmann::json* json) {
  nlohmann::json described;
  if (source.simulated) {
    nlohmann::json hidden = nlohmann::json::object();
    for (const auto& [name, value] : source.hidden) hidden[name] = value;
    described = {{"kind", "simulated"},
                 {"scenario", source.scenario},
                 {"seed", source.seed},
                 {"hidden", hidden}};
  } else {
    described = {{"kind", "measured"},
                 {"data_dir", source.data_dir.empty() ? nlohmann::json(nullptr)
                                                      : nlohmann::json(source.data_dir)}};
  }
  (*json)["source"] = described;
  (*json)["input_files"] = InputFilesJson(source.files);
  (*json)["command_line"] = CommandLine();
  (*json)["accelcal_version"] = AccelcalVersion();
}

void RecordCommandLine(int argc, char** argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    std::string argument = argv[i];
    // The program by its name, not by the path it was started with.
    if (i == 0) argument = argument.substr(argument.rfind('/') + 1);
    line += (i == 0 ? "" : " ") + ShellWord(argument);
  }
  RecordedCommandLine() = line;
}

const std::string& CommandLine() { return RecordedCommandLine(); }

}  // namespace accelcal
