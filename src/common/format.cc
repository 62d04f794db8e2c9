#include "common/format.h"

#include <cctype>
#include <charconv>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace accelcal {

std::string StringPrintf(const char* format, ...) {
  va_list arguments;
  va_start(arguments, format);
  va_list copy;
  va_copy(copy, arguments);
  const int length = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  std::vector<char> buffer(length > 0 ? length + 1 : 1, '\0');
  if (length > 0) std::vsnprintf(buffer.data(), buffer.size(), format, arguments);
  va_end(arguments);
  return std::string(buffer.data(), length > 0 ? length : 0);
}

std::string RoundTripDouble(double value) {
  for (int precision = 15; precision < 17; ++precision) {
    const std::string text = StringPrintf("%.*g", precision, value);
    if (std::strtod(text.c_str(), nullptr) == value) return text;
  }
  return StringPrintf("%.17g", value);
}

void AppendGeneral(double value, int precision, std::string* text) {
  char buffer[64];
  const std::to_chars_result end =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::general, precision);
  text->append(buffer, end.ptr);
}

void AppendRoundTripDouble(double value, std::string* text) {
  char buffer[64];
  for (int precision = 15; precision < 17; ++precision) {
    const std::to_chars_result end = std::to_chars(buffer, buffer + sizeof(buffer), value,
                                                   std::chars_format::general, precision);
    double read = 0.0;
    const std::from_chars_result parsed = std::from_chars(buffer, end.ptr, read);
    if (parsed.ec == std::errc() && read == value) {
      text->append(buffer, end.ptr);
      return;
    }
  }
  AppendGeneral(value, 17, text);
}

std::string JoinStrings(const std::vector<std::string>& items, const char* separator) {
  std::string text;
  for (size_t i = 0; i < items.size(); ++i) text += (i == 0 ? "" : separator) + items[i];
  return text;
}

std::string FormatTriple(const std::array<double, 3>& v, const char* format) {
  return "(" + StringPrintf(format, v[0]) + ", " + StringPrintf(format, v[1]) + ", " +
         StringPrintf(format, v[2]) + ")";
}

std::string LowerAscii(std::string_view text) {
  std::string lowered(text);
  for (char& c : lowered) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lowered;
}

}  // namespace accelcal
