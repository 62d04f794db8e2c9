#ifndef ACCELCAL_COMMON_FORMAT_H_
#define ACCELCAL_COMMON_FORMAT_H_

// printf-style formatting into a std::string, for tables and one-line error messages.

#include <string>

namespace accelcal {

std::string StringPrintf(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_FORMAT_H_
