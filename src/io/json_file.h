#ifndef ACCELCAL_IO_JSON_FILE_H_
#define ACCELCAL_IO_JSON_FILE_H_

// Every JSON file the binaries write goes through here. nlohmann::json writes NaN and
// infinities as `null` without a word, so a result that went non-finite would reach the
// reader as a missing value; this refuses to write it instead, naming where it is.

#include <nlohmann/json.hpp>
#include <string>

#include "common/status.h"

namespace accelcal {

// The JSON pointer (e.g. "/joint/estimate/0/sigma") of the first non-finite number in
// `json`, or "" when every number is finite.
std::string FirstNonFiniteNumber(const nlohmann::json& json);

// Writes `json` (indented, newline-terminated) atomically (io/atomic_file.h), after
// checking that every number in it is finite; otherwise writes nothing and fails.
Status WriteJsonAtomically(const std::string& path, const nlohmann::json& json);

}  // namespace accelcal

#endif  // ACCELCAL_IO_JSON_FILE_H_
