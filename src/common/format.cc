#include "common/format.h"

#include <cstdarg>
#include <cstdio>
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

}  // namespace accelcal
