#include "io/ros2_imu_message.h"

#include <cmath>
#include <cstring>

#include "common/format.h"

namespace accelcal {
namespace {

constexpr size_t kEncapsulationBytes = 4;
// The longest frame_id taken: a frame's name is a few words, a longer string is a damaged length.
constexpr uint32_t kMaxFrameIdBytes = 1 << 16;

// Reads CDR version 1 fields from the bytes after the encapsulation header, each aligned to its
// size relative to their first byte, checking every read against the end.
class CdrReader {
 public:
  CdrReader(std::string_view body, bool big_endian) : body_(body), big_endian_(big_endian) {}

  Status Uint32(const char* field, uint32_t* value) {
    uint8_t bytes[4];
    ACCELCAL_RETURN_IF_ERROR(Take(field, 4, bytes));
    *value = 0;
    for (int i = 0; i < 4; ++i) {
      const int shift = big_endian_ ? 8 * (3 - i) : 8 * i;
      *value |= static_cast<uint32_t>(bytes[i]) << shift;
    }
    return Status::Ok();
  }

  Status Float64(const char* field, double* value) {
    uint8_t bytes[8];
    ACCELCAL_RETURN_IF_ERROR(Take(field, 8, bytes));
    uint64_t bits = 0;
    for (int i = 0; i < 8; ++i) {
      const int shift = big_endian_ ? 8 * (7 - i) : 8 * i;
      bits |= static_cast<uint64_t>(bytes[i]) << shift;
    }
    std::memcpy(value, &bits, sizeof(bits));
    return Status::Ok();
  }

  template <size_t N>
  Status Float64s(const char* field, std::array<double, N>* values) {
    for (double& value : *values) ACCELCAL_RETURN_IF_ERROR(Float64(field, &value));
    return Status::Ok();
  }

  Status String(const char* field, std::string* value) {
    uint32_t length = 0;
    ACCELCAL_RETURN_IF_ERROR(Uint32(field, &length));
    if (length == 0 || length > kMaxFrameIdBytes) {
      return Status::Error(StringPrintf(
          "%s: a string length of %u at byte %zu (CDR counts the closing NUL, 1 to %u)", field,
          length, kEncapsulationBytes + offset_ - 4, kMaxFrameIdBytes));
    }
    if (length > body_.size() - offset_) return CutShort(field, length);
    if (body_[offset_ + length - 1] != '\0') {
      return Status::Error(StringPrintf("%s: the string at byte %zu does not end in NUL", field,
                                        kEncapsulationBytes + offset_));
    }
    value->assign(body_.data() + offset_, length - 1);
    offset_ += length;
    return Status::Ok();
  }

  size_t unread() const { return body_.size() - offset_; }

 private:
  Status Take(const char* field, size_t size, uint8_t* bytes) {
    const size_t aligned = (offset_ + size - 1) / size * size;
    if (aligned > body_.size() || size > body_.size() - aligned) return CutShort(field, size);
    std::memcpy(bytes, body_.data() + aligned, size);
    offset_ = aligned + size;
    return Status::Ok();
  }

  Status CutShort(const char* field, size_t size) const {
    return Status::Error(StringPrintf(
        "the message is cut short: %s needs %zu bytes from byte %zu, the message has %zu", field,
        size, kEncapsulationBytes + offset_, kEncapsulationBytes + body_.size()));
  }

  std::string_view body_;
  bool big_endian_;
  size_t offset_ = 0;
};

// Appends CDR version 1 fields, aligned as CdrReader reads them.
class CdrWriter {
 public:
  explicit CdrWriter(bool big_endian) : big_endian_(big_endian) {}
  void Uint32(uint32_t value) {
    Align(4);
    for (int i = 0; i < 4; ++i) body_.push_back(static_cast<char>(value >> Shift(i, 4)));
  }
  void Float64(double value) {
    Align(8);
    uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof(bits));
    for (int i = 0; i < 8; ++i) body_.push_back(static_cast<char>(bits >> Shift(i, 8)));
  }
  template <size_t N>
  void Float64s(const std::array<double, N>& values) {
    for (double value : values) Float64(value);
  }
  void String(const std::string& value) {
    Uint32(static_cast<uint32_t>(value.size() + 1));
    body_ += value;
    body_.push_back('\0');
  }
  const std::string& body() const { return body_; }

 private:
  int Shift(int i, int size) const { return big_endian_ ? 8 * (size - 1 - i) : 8 * i; }
  void Align(size_t size) { body_.resize((body_.size() + size - 1) / size * size, '\0'); }
  bool big_endian_;
  std::string body_;
};

}  // namespace

Status DecodeRos2ImuMessage(std::string_view data, Ros2ImuMessage* message) {
  *message = Ros2ImuMessage();
  if (data.size() < kEncapsulationBytes) {
    return Status::Error(StringPrintf(
        "the message is cut short: %zu bytes, not even CDR's 4-byte encapsulation header",
        data.size()));
  }
  const uint8_t kind_high = static_cast<uint8_t>(data[0]);
  const uint8_t kind_low = static_cast<uint8_t>(data[1]);
  if (kind_high != 0 || kind_low > 1) {
    return Status::Error(StringPrintf(
        "encapsulation 0x%02x 0x%02x is not CDR version 1 (0x00 0x01 little-endian, 0x00 0x00 "
        "big-endian), the only serialization of ROS 2's 'cdr' format read here; re-record the bag "
        "with a ROS 2 middleware's default (XCDR1) serialization",
        kind_high, kind_low));
  }
  CdrReader reader(data.substr(kEncapsulationBytes), kind_low == 0);
  uint32_t sec = 0;
  ACCELCAL_RETURN_IF_ERROR(reader.Uint32("header.stamp.sec", &sec));
  message->stamp_sec = static_cast<int32_t>(sec);
  ACCELCAL_RETURN_IF_ERROR(reader.Uint32("header.stamp.nanosec", &message->stamp_nanosec));
  ACCELCAL_RETURN_IF_ERROR(reader.String("header.frame_id", &message->frame_id));
  ACCELCAL_RETURN_IF_ERROR(reader.Float64s("orientation", &message->orientation));
  ACCELCAL_RETURN_IF_ERROR(
      reader.Float64s("orientation_covariance", &message->orientation_covariance));
  ACCELCAL_RETURN_IF_ERROR(reader.Float64s("angular_velocity", &message->angular_velocity_radps));
  ACCELCAL_RETURN_IF_ERROR(
      reader.Float64s("angular_velocity_covariance", &message->angular_velocity_covariance));
  ACCELCAL_RETURN_IF_ERROR(
      reader.Float64s("linear_acceleration", &message->linear_acceleration_mps2));
  ACCELCAL_RETURN_IF_ERROR(
      reader.Float64s("linear_acceleration_covariance", &message->linear_acceleration_covariance));
  // CDR pads a message to a multiple of 4 bytes at most; more is not an Imu message.
  if (reader.unread() >= 8) {
    return Status::Error(StringPrintf(
        "%zu bytes after linear_acceleration_covariance, the last field of sensor_msgs/msg/Imu: "
        "the message is of another type",
        reader.unread()));
  }
  if (message->stamp_nanosec >= 1000000000u) {
    return Status::Error(StringPrintf(
        "header.stamp.nanosec = %u is not below 1e9: not a time stamp", message->stamp_nanosec));
  }
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(message->angular_velocity_radps[k]) ||
        !std::isfinite(message->linear_acceleration_mps2[k])) {
      return Status::Error(StringPrintf(
          "angular_velocity (%g, %g, %g) or linear_acceleration (%g, %g, %g) holds a value that is "
          "not a finite number",
          message->angular_velocity_radps[0], message->angular_velocity_radps[1],
          message->angular_velocity_radps[2], message->linear_acceleration_mps2[0],
          message->linear_acceleration_mps2[1], message->linear_acceleration_mps2[2]));
    }
  }
  return Status::Ok();
}

std::string EncodeRos2ImuMessage(const Ros2ImuMessage& message, bool big_endian) {
  CdrWriter writer(big_endian);
  writer.Uint32(static_cast<uint32_t>(message.stamp_sec));
  writer.Uint32(message.stamp_nanosec);
  writer.String(message.frame_id);
  writer.Float64s(message.orientation);
  writer.Float64s(message.orientation_covariance);
  writer.Float64s(message.angular_velocity_radps);
  writer.Float64s(message.angular_velocity_covariance);
  writer.Float64s(message.linear_acceleration_mps2);
  writer.Float64s(message.linear_acceleration_covariance);
  std::string data = {'\0', big_endian ? '\0' : '\x01', '\0', '\0'};
  return data + writer.body();
}

}  // namespace accelcal
