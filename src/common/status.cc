#include "common/status.h"

namespace accelcal {

Status Status::WithContext(const std::string& context) const {
  if (ok()) return *this;
  return Status(context + ": " + message_);
}

}  // namespace accelcal
