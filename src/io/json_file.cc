#include "io/json_file.h"

#include <cmath>

#include "io/atomic_file.h"

namespace accelcal {
namespace {

std::string FindNonFinite(const nlohmann::json& json, const std::string& pointer) {
  if (json.is_number_float()) {
    return std::isfinite(json.get<double>()) ? "" : (pointer.empty() ? "/" : pointer);
  }
  if (json.is_object()) {
    for (auto it = json.begin(); it != json.end(); ++it) {
      const std::string found = FindNonFinite(it.value(), pointer + "/" + it.key());
      if (!found.empty()) return found;
    }
  } else if (json.is_array()) {
    for (size_t i = 0; i < json.size(); ++i) {
      const std::string found = FindNonFinite(json[i], pointer + "/" + std::to_string(i));
      if (!found.empty()) return found;
    }
  }
  return "";
}

}  // namespace

std::string FirstNonFiniteNumber(const nlohmann::json& json) { return FindNonFinite(json, ""); }

Status WriteJsonAtomically(const std::string& path, const nlohmann::json& json) {
  const std::string where = FirstNonFiniteNumber(json);
  if (!where.empty()) {
    return Status::Error("the result holds a non-finite number at " + where +
                         ", so nothing was written; this is a bug, please report it with the "
                         "command line and data");
  }
  return WriteFileAtomically(path, json.dump(2) + "\n");
}

}  // namespace accelcal
