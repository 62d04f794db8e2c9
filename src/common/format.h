#ifndef ACCELCAL_COMMON_FORMAT_H_
#define ACCELCAL_COMMON_FORMAT_H_

// printf-style formatting into a std::string, for tables and one-line error messages.

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace accelcal {

std::string StringPrintf(const char* format, ...) __attribute__((format(printf, 1, 2)));

// "a<separator>b<separator>c" ("" for none).
std::string JoinStrings(const std::vector<std::string>& items, const char* separator = ", ");

// "(x, y, z)", each value printed with `format` (one printf conversion of a double).
std::string FormatTriple(const std::array<double, 3>& v, const char* format = "%.6g");

// The shortest decimal (15 to 17 significant digits) that reads back as exactly `value`:
// 0.64 rather than 0.64000000000000001.
std::string RoundTripDouble(double value);

// The same digits appended to `text` without a temporary string: std::to_chars at 15, 16 and
// 17 significant digits (the digits printf's %.*g gives), read back by std::from_chars. Five to
// ten times faster than RoundTripDouble, for writers of millions of values (apply).
void AppendRoundTripDouble(double value, std::string* text);

// printf's "%.<precision>g" of `value` appended to `text` (std::to_chars, the same digits).
void AppendGeneral(double value, int precision, std::string* text);

// `text` with its ASCII letters in lower case (other bytes, UTF-8 among them, unchanged).
std::string LowerAscii(std::string_view text);

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_FORMAT_H_
