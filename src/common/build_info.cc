#include "common/build_info.h"

#include "git_commit.h"  // generated: ACCELCAL_GIT_COMMIT

#ifndef ACCELCAL_VERSION
#error "ACCELCAL_VERSION must be defined by the build (src/CMakeLists.txt)"
#endif
#ifndef ACCELCAL_BUILD_TYPE
#error "ACCELCAL_BUILD_TYPE must be defined by the build (src/CMakeLists.txt)"
#endif

namespace accelcal {

const char* AccelcalGitCommit() { return ACCELCAL_GIT_COMMIT; }

const char* AccelcalBuildType() {
  return ACCELCAL_BUILD_TYPE[0] == '\0' ? "unspecified" : ACCELCAL_BUILD_TYPE;
}

std::string BuildInfoLine() {
  return std::string(ACCELCAL_VERSION) + " (commit " + AccelcalGitCommit() + ", " +
         AccelcalBuildType() + " build)";
}

}  // namespace accelcal
