#ifndef ACCELCAL_COMMON_LINE_TEXT_H_
#define ACCELCAL_COMMON_LINE_TEXT_H_

// One rule for any text (a path, a name, a message) that reaches a line-oriented output: a
// CSV's '#' provenance lines, a YAML or .calib comment, a Markdown report, a first line on
// stdout. Written raw, a path holding a line break would end its line and start one of its own:
// a key Kalibr reads from imu.yaml, a line without '#' that a CSV reader takes for the header.
// JSON needs none of this (its strings escape every control character).

#include <string>
#include <string_view>

namespace accelcal {

// `text` as part of one line, every line break and control character escaped, the rest as it
// is:
//   \n \r \t                         as \n, \r, \t (a backslash and a letter)
//   other C0 controls and DEL        as \xNN (two upper-case hex digits)
//   NEL, LS, PS (U+0085, U+2028,     as \u0085, \u2028, \u2029: YAML, JavaScript and some
//   U+2029, in UTF-8)                editors break lines at them
//   a byte that is not UTF-8         as \xNN, so that the output stays valid UTF-8
// Text without any of these (every ordinary path) comes back unchanged.
std::string EscapeForLine(std::string_view text);

// Whether EscapeForLine would change `text`.
bool NeedsLineEscape(std::string_view text);

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_LINE_TEXT_H_
