// libFuzzer target: the .mat loaders (our MAT5 integrity walk, then libmatio) on arbitrary
// bytes, read as a tilt test, a run and a landmark file. The bytes are handed over as an
// in-memory file (memfd), since matio reads only from a path. Every input must give a
// Status; an accepted one must be internally consistent.

#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/course_data.h"

namespace {

void CheckTest(const accelcal::CalibrationTest& test) {
  if (test.measured_x.size() != test.theta_rad.size() ||
      test.measured_y.size() != test.theta_rad.size() || test.theta_rad.empty()) {
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const int fd = memfd_create("accelcal_fuzz.mat", 0);
  if (fd < 0) std::abort();
  if (ftruncate(fd, 0) != 0 || pwrite(fd, data, size, 0) != static_cast<ssize_t>(size)) {
    std::abort();
  }
  const std::string path = "/proc/self/fd/" + std::to_string(fd);

  accelcal::CalibrationTest test;
  std::vector<std::string> notes;
  if (accelcal::LoadCalibrationTest(path, &test, {}, &notes).ok()) CheckTest(test);
  accelcal::VehicleRun run;
  if (accelcal::LoadVehicleRun(path, &run, &notes).ok()) {
    if (run.measured_x.size() != run.timestamp_s.size() || run.timestamp_s.size() < 2) {
      std::abort();
    }
  }
  std::vector<accelcal::Landmark> landmarks;
  if (accelcal::LoadLandmarks(path, &landmarks).ok()) {
    for (const accelcal::Landmark& landmark : landmarks) {
      if (!std::isfinite(landmark.x_m) || !std::isfinite(landmark.y_m)) std::abort();
    }
  }
  return 0;
}
