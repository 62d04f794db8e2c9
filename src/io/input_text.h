#ifndef ACCELCAL_IO_INPUT_TEXT_H_
#define ACCELCAL_IO_INPUT_TEXT_H_

// Quoting a file's own text in a message. A reader that says "'abc' is not a number" must
// not echo whatever the file holds: a 5 MB cell would make a 5 MB message, and a NUL or a
// carriage return would break the one line a user reads. What the readers quote goes
// through EchoInput first.

#include <cstddef>
#include <string>
#include <string_view>

namespace accelcal {

// Characters of input text a message quotes; longer text is cut there and ends in "...".
constexpr size_t kMaxEchoCharacters = 40;

// `text` made fit for a one-line message: at most kMaxEchoCharacters characters, then "..."
// when it was longer; a byte that is not printable (ASCII control characters, DEL, C1
// controls, and bytes that are not part of a valid UTF-8 character, such as Latin-1 accents)
// is written as \xNN. Valid UTF-8 (accented Spanish keys) is kept as it is.
std::string EchoInput(std::string_view text);

// Whether `text` is valid UTF-8 with no control characters (C0, DEL or C1): what a name may
// be that appears in tables and in JSON, which must be UTF-8.
bool IsPrintableUtf8(std::string_view text);

}  // namespace accelcal

#endif  // ACCELCAL_IO_INPUT_TEXT_H_
