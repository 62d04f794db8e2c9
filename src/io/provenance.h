#ifndef ACCELCAL_IO_PROVENANCE_H_
#define ACCELCAL_IO_PROVENANCE_H_

// Where a result's data came from, said the same way by every binary: first on stdout,
//
//   data: ../shared/data/tp2-2018 (4 files)
//   data: simulated, scenario tp2-2018, seed 1, hidden angle_offset=0.004
//
// and in every JSON output as
//
//   "source": {"kind": "measured", "data_dir": "../shared/data/tp2-2018"}
//          or {"kind": "simulated", "scenario": "tp2-2018", "seed": 1,
//              "hidden": {"angle_offset": 0.004}}
//   "input_files": {"calibration": {"path": ..., "bytes": 480248, "sha256": "9f86..."}, ...}
//   "command_line": "linear_ls --data_dir=../shared/data/tp2-2018 --json=out.json"
//   "accelcal_version": "0.1.0"
//
// so that a number can be traced to the exact files (`sha256sum`) or the exact simulation
// (scenario and seed reproduce it) and the command that produced it. docs/json.md states it.

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "common/status.h"

namespace accelcal {

// The version of this tool, as the project's CMakeLists.txt states it.
const char* AccelcalVersion();

struct InputFile {
  std::string path;
  uint64_t bytes = 0;
  std::string sha256;  // 64 lowercase hex digits
};

// The bytes and SHA-256 of `path` (a regular file): those a reader of this run parsed, when one
// did (io/input_file.h, RecordInputRead), provided the file is unchanged since (refused
// otherwise: the checksum would not be of the bytes the results came from); else the file read
// whole through SHA-256 in bounded memory, and recorded.
Status HashInputFile(const std::string& path, InputFile* file);

struct DataSource {
  bool simulated = false;
  // Measured data: the folder given (empty when every file was named by itself).
  std::string data_dir;
  // Every file read, by role ("calibration", "run", "landmarks", "conditions", "scenario",
  // "log", ...); a simulation lists the scenario file it read, if any.
  std::map<std::string, InputFile> files;
  // Simulated data: the scenario, the seed (the first of a study's seeds) and what the
  // scenario hides beyond the baseline, name and value ("angle_offset", 0.004).
  std::string scenario;
  uint64_t seed = 0;
  std::vector<std::pair<std::string, double>> hidden;
};

// A measured source: every non-empty path of `files` (role -> path) hashed; a folder a reader
// recorded (RecordInputFolder, a ROS 2 bag's) as its files, role + suffix each.
Status DescribeMeasuredData(const std::string& data_dir,
                            const std::map<std::string, std::string>& files, DataSource* source);

// The first line of every binary's output ("data: ...", no newline).
std::string DataLine(const DataSource& source);

// The provenance keys of every JSON output: source, input_files, command_line,
// accelcal_version.
void AddProvenanceJson(const DataSource& source, nlohmann::json* json);
nlohmann::json InputFilesJson(const std::map<std::string, InputFile>& files);

// The current time in UTC, formatted by strftime's `format` (e.g. "%Y-%m-%dT%H:%M:%SZ").
std::string UtcNow(const char* format);

// The command line as typed, each argument quoted for a POSIX shell where needed. Recorded
// once by each binary before its flags are parsed (problems/problem_support.h).
void RecordCommandLine(int argc, char** argv);
const std::string& CommandLine();

}  // namespace accelcal

#endif  // ACCELCAL_IO_PROVENANCE_H_
