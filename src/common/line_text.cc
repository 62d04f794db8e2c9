#include "common/line_text.h"

#include <cstdio>

namespace accelcal {
namespace {

// The length of the valid UTF-8 sequence of two to four bytes that starts `text` at `i`, or 0
// (a lone continuation byte, an overlong form, a surrogate, beyond U+10FFFF, or cut short).
size_t Utf8SequenceLength(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  size_t length = 0;
  unsigned char low = 0x80, high = 0xBF;  // the range of the second byte
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;   // no overlong form
    if (lead == 0xED) high = 0x9F;  // no surrogate
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;   // no overlong form
    if (lead == 0xF4) high = 0x8F;  // nothing beyond U+10FFFF
  } else {
    return 0;
  }
  if (i + length > text.size()) return 0;
  if (byte(i + 1) < low || byte(i + 1) > high) return 0;
  for (size_t k = 2; k < length; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  return length;
}

// Appends the escape of the unit of `text` at `i` (one byte, or one UTF-8 sequence) to `out`
// when it needs one, or the unit itself; returns the unit's length. `out` may be null: then
// only whether it needed one is told, through `escaped`.
size_t EscapeUnit(std::string_view text, size_t i, std::string* out, bool* escaped) {
  const unsigned char c = static_cast<unsigned char>(text[i]);
  char buffer[8];
  const char* escape = nullptr;
  size_t length = 1;
  if (c == '\n') {
    escape = "\\n";
  } else if (c == '\r') {
    escape = "\\r";
  } else if (c == '\t') {
    escape = "\\t";
  } else if (c < 0x20 || c == 0x7F) {
    std::snprintf(buffer, sizeof(buffer), "\\x%02X", c);
    escape = buffer;
  } else if (c >= 0x80) {
    length = Utf8SequenceLength(text, i);
    if (length == 0) {
      length = 1;
      std::snprintf(buffer, sizeof(buffer), "\\x%02X", c);
      escape = buffer;
    } else if (text.substr(i, length) == "\xC2\x85") {
      escape = "\\u0085";
    } else if (text.substr(i, length) == "\xE2\x80\xA8") {
      escape = "\\u2028";
    } else if (text.substr(i, length) == "\xE2\x80\xA9") {
      escape = "\\u2029";
    }
  }
  if (escape != nullptr) *escaped = true;
  if (out != nullptr) {
    if (escape != nullptr) {
      out->append(escape);
    } else {
      out->append(text.substr(i, length));
    }
  }
  return length;
}

}  // namespace

std::string EscapeForLine(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  bool escaped = false;
  for (size_t i = 0; i < text.size();) i += EscapeUnit(text, i, &out, &escaped);
  return out;
}

bool NeedsLineEscape(std::string_view text) {
  bool escaped = false;
  for (size_t i = 0; i < text.size() && !escaped;) i += EscapeUnit(text, i, nullptr, &escaped);
  return escaped;
}

}  // namespace accelcal
