#include "io/imucal_calibration_json.h"

#include <cmath>

#include "io/input_file.h"
#include "io/json_file.h"

namespace accelcal {
namespace {

// A finite number, or a message naming `where` it is not.
Status Number(const nlohmann::json& json, const std::string& where, double* value) {
  if (!json.is_number() || !std::isfinite(json.get<double>())) {
    return Status::Error(where + " is " + json.dump() + ", not a finite number");
  }
  *value = json.get<double>();
  return Status::Ok();
}

Status Vector(const nlohmann::json& document, const char* key, Eigen::Vector3d* vector) {
  const nlohmann::json& json = document.at(key);
  if (!json.is_array() || json.size() != 3) {
    return Status::Error(std::string(key) + " must be an array of 3 numbers");
  }
  for (int i = 0; i < 3; ++i) {
    ACCELCAL_RETURN_IF_ERROR(
        Number(json[i], std::string(key) + "[" + std::to_string(i) + "]", &(*vector)[i]));
  }
  return Status::Ok();
}

Status Matrix(const nlohmann::json& document, const char* key, Eigen::Matrix3d* matrix) {
  const nlohmann::json& json = document.at(key);
  bool shaped = json.is_array() && json.size() == 3;
  for (size_t i = 0; shaped && i < 3; ++i) shaped = json[i].is_array() && json[i].size() == 3;
  if (!shaped)
    return Status::Error(std::string(key) + " must be a 3x3 array (3 rows of 3 numbers)");
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      ACCELCAL_RETURN_IF_ERROR(Number(
          json[i][j], std::string(key) + "[" + std::to_string(i) + "][" + std::to_string(j) + "]",
          &(*matrix)(i, j)));
    }
  }
  return Status::Ok();
}

}  // namespace

Status ParseImucalCalibrationJson(const std::string& text, ImucalCalibration* calibration) {
  *calibration = ImucalCalibration();
  nlohmann::json document;
  ACCELCAL_RETURN_IF_ERROR(ParseJsonStrict(text, &document));
  if (!document.is_object()) return Status::Error("not a JSON object: not an imucal calibration");
  for (const char* key : {"K_a", "R_a", "b_a"}) {
    if (!document.contains(key)) {
      return Status::Error(std::string("no key \"") + key +
                           "\": an imucal calibration has K_a, R_a and b_a");
    }
  }
  ImucalAccelerometer& acc = calibration->accelerometer;
  ACCELCAL_RETURN_IF_ERROR(Matrix(document, "K_a", &acc.k_a));
  ACCELCAL_RETURN_IF_ERROR(Matrix(document, "R_a", &acc.r_a));
  ACCELCAL_RETURN_IF_ERROR(Vector(document, "b_a", &acc.b_a));
  int gyroscope_keys = 0;
  for (const char* key : {"K_g", "R_g", "K_ga", "b_g"})
    gyroscope_keys += document.contains(key) && !document.at(key).is_null();
  if (gyroscope_keys == 0) return Status::Ok();
  if (gyroscope_keys != 4) {
    return Status::Error(
        "the gyroscope is given in part: a Ferraris calibration has all of K_g, R_g, K_ga and "
        "b_g, or none");
  }
  ImucalGyroscope& gyr = calibration->gyroscope;
  ACCELCAL_RETURN_IF_ERROR(Matrix(document, "K_g", &gyr.k_g));
  ACCELCAL_RETURN_IF_ERROR(Matrix(document, "R_g", &gyr.r_g));
  ACCELCAL_RETURN_IF_ERROR(Matrix(document, "K_ga", &gyr.k_ga));
  ACCELCAL_RETURN_IF_ERROR(Vector(document, "b_g", &gyr.b_g));
  calibration->has_gyroscope = true;
  return Status::Ok();
}

Status ReadImucalCalibrationJson(const std::string& path, ImucalCalibration* calibration) {
  std::string text;
  ACCELCAL_RETURN_IF_ERROR(
      ReadInputText(path, kMaxConditionsFileBytes, "an imucal calibration (JSON)", &text)
          .WithContext(path));
  return ParseImucalCalibrationJson(text, calibration).WithContext(path);
}

namespace {

nlohmann::ordered_json MatrixJson(const Eigen::Matrix3d& matrix) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({matrix(i, 0), matrix(i, 1), matrix(i, 2)});
  return rows;
}

nlohmann::ordered_json VectorJson(const Eigen::Vector3d& vector) {
  return {vector[0], vector[1], vector[2]};
}

}  // namespace

std::string ImucalCalibrationJsonText(const ImucalCalibration& calibration,
                                      const ImucalUnits& units) {
  // FerrarisCalibrationInfo's fields in its dataclass order, then cal_type and _format_version
  // (CalibrationInfo._to_list_dict).
  nlohmann::ordered_json json;
  json["acc_unit"] = units.acc_unit;
  json["gyr_unit"] = units.gyr_unit;
  json["from_acc_unit"] = units.from_acc_unit;
  json["from_gyr_unit"] = units.from_gyr_unit;
  json["comment"] = units.comment.empty() ? nlohmann::ordered_json(nullptr)
                                          : nlohmann::ordered_json(units.comment);
  const ImucalAccelerometer& acc = calibration.accelerometer;
  const ImucalGyroscope& gyr = calibration.gyroscope;
  json["K_a"] = MatrixJson(acc.k_a);
  json["R_a"] = MatrixJson(acc.r_a);
  json["b_a"] = VectorJson(acc.b_a);
  json["K_g"] = MatrixJson(gyr.k_g);
  json["R_g"] = MatrixJson(gyr.r_g);
  json["K_ga"] = MatrixJson(gyr.k_ga);
  json["b_g"] = VectorJson(gyr.b_g);
  json["cal_type"] = "Ferraris";
  json["_format_version"] = "2.0.0";
  return json.dump(4) + "\n";
}

}  // namespace accelcal
