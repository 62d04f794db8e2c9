#ifndef ACCELCAL_COMMON_BUILD_INFO_H_
#define ACCELCAL_COMMON_BUILD_INFO_H_

// What was built: the version (CMake's project version), the git commit of the checkout it was
// built from (12 hex digits, "-modified" when tracked files differed, "unknown" outside a
// checkout; cmake/git_commit.cmake, refreshed at every build) and the build type. Every binary's
// --version prints BuildInfoLine().

#include <string>

namespace accelcal {

const char* AccelcalGitCommit();
const char* AccelcalBuildType();  // "Release", "Debug", ... or "unspecified"
// "0.1.0 (commit 0123456789ab, Release build)".
std::string BuildInfoLine();

}  // namespace accelcal

#endif  // ACCELCAL_COMMON_BUILD_INFO_H_
