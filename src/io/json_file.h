#ifndef ACCELCAL_IO_JSON_FILE_H_
#define ACCELCAL_IO_JSON_FILE_H_

// Every JSON file the binaries write goes through here. nlohmann::json writes NaN and
// infinities as `null` without a word, so a result that went non-finite would reach the
// reader as a missing value; this refuses to write it instead, naming where it is.
//
// And every JSON file they read: nlohmann::json keeps the last of two values given for one
// key, so a scenario that says "dt" twice would be simulated with whichever came last;
// ParseJsonStrict refuses it, naming the key and where it is.

#include <nlohmann/json.hpp>
#include <string>

#include "common/status.h"

namespace accelcal {

// The JSON pointer (e.g. "/joint/estimate/0/sigma") of the first non-finite number in
// `json`, or "" when every number is finite.
std::string FirstNonFiniteNumber(const nlohmann::json& json);

// The deepest nesting of arrays and objects ParseJsonStrict accepts. No accelcal input nests
// beyond a few levels, and nlohmann::json copies, compares and prints a document by recursion,
// so a crafted file of a hundred thousand '[' would overflow the stack in whatever first copied
// it; the parser itself is iterative, and stops at the first level too deep.
constexpr int kMaxJsonDepth = 64;

// Parses `text` as one JSON document into `document`. Fails on invalid JSON ("not valid
// JSON (...)", the parser's message with the text it quotes cut to EchoInput's length), on
// arrays and objects nested deeper than kMaxJsonDepth ("arrays and objects nested more than 64
// deep, under /model; ..."), and on a key given twice in one object: 'key "dt" is given twice
// in one object, at /run/dt; ...' (the second occurrence's JSON pointer, RFC 6901). On failure
// `document` is null.
Status ParseJsonStrict(const std::string& text, nlohmann::json* document);

// Writes `json` (indented, newline-terminated) atomically (io/atomic_file.h), after
// checking that every number in it is finite; otherwise writes nothing and fails.
Status WriteJsonAtomically(const std::string& path, const nlohmann::json& json);

// The text WriteJsonAtomically writes (indented, a final newline, any string that is not
// UTF-8 written with U+FFFD), or the same refusal of a non-finite number; for binaries that
// write several outputs at once (WriteFilesAtomically).
Status JsonText(const nlohmann::json& json, std::string* text);

}  // namespace accelcal

#endif  // ACCELCAL_IO_JSON_FILE_H_
