#include "io/input_text.h"

#include <cstdio>

namespace accelcal {
namespace {

// The length of the valid UTF-8 character of two or more bytes starting at text[at], or 0
// when there is none (a stray continuation byte, a truncated or overlong sequence, a
// surrogate, or a C1 control character, which prints as nothing readable).
size_t Utf8CharacterLength(std::string_view text, size_t at) {
  const unsigned char lead = static_cast<unsigned char>(text[at]);
  size_t length;
  unsigned char low = 0x80;  // the allowed range of the second byte
  unsigned char high = 0xBF;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
    if (lead == 0xC2) low = 0xA0;  // U+0080..U+009F are the C1 controls
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;   // overlong
    if (lead == 0xED) high = 0x9F;  // surrogates
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;   // overlong
    if (lead == 0xF4) high = 0x8F;  // beyond U+10FFFF
  } else {
    return 0;
  }
  if (at + length > text.size()) return 0;
  for (size_t k = 1; k < length; ++k) {
    const unsigned char byte = static_cast<unsigned char>(text[at + k]);
    if (byte < (k == 1 ? low : 0x80) || byte > (k == 1 ? high : 0xBF)) return 0;
  }
  return length;
}

}  // namespace

std::string EchoInput(std::string_view text) {
  std::string echo;
  size_t characters = 0;
  size_t at = 0;
  while (at < text.size() && characters < kMaxEchoCharacters) {
    const unsigned char byte = static_cast<unsigned char>(text[at]);
    if (byte >= 0x20 && byte < 0x7F) {
      echo.push_back(static_cast<char>(byte));
      ++at;
    } else if (const size_t length = byte >= 0x80 ? Utf8CharacterLength(text, at) : 0) {
      echo.append(text.substr(at, length));
      at += length;
    } else {
      char escape[5];
      std::snprintf(escape, sizeof(escape), "\\x%02X", byte);
      echo += escape;
      ++at;
    }
    ++characters;
  }
  if (at < text.size()) echo += "...";
  return echo;
}

bool IsPrintableUtf8(std::string_view text) {
  for (size_t at = 0; at < text.size();) {
    const unsigned char byte = static_cast<unsigned char>(text[at]);
    if (byte < 0x20 || byte == 0x7f) return false;
    if (byte < 0x80) {
      ++at;
      continue;
    }
    const size_t length = Utf8CharacterLength(text, at);
    if (length == 0) return false;
    at += length;
  }
  return true;
}

}  // namespace accelcal
