#ifndef ACCELCAL_COMMON_FORMAT_H_
#define ACCELCAL_COMMON_FORMAT_H_

// printf-style formatting into a std::string, for tables and one-line error messages.

#include <string>

namespace accelcal {

std::string StringPrintf(const char* format, ...) __attribute__((format(printf, 1, 2)));

// The shortest decimal (15 to 17 significant digits) that reads back as exactly `value`:
// 0.64 rather than 0.64000000000000001.
std::string RoundTripDouble(double value);

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_FORMAT_H_
