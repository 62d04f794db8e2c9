// libFuzzer target: the datos.txt parser on arbitrary bytes. Every input must give a
// Status; an accepted one must hold finite values and positive variances.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "io/datos_txt.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  accelcal::RunConditions conditions;
  if (!accelcal::ParseDatosTxt(text, &conditions).ok()) return 0;
  const double values[] = {conditions.initial_position_x_m,   conditions.initial_position_y_m,
                           conditions.initial_velocity_x_mps, conditions.initial_velocity_y_mps,
                           conditions.noise_variance_x,       conditions.noise_variance_y};
  for (const double value : values) {
    if (!std::isfinite(value)) std::abort();
  }
  if (!(conditions.noise_variance_x > 0.0 && conditions.noise_variance_y > 0.0)) std::abort();
  return 0;
}
