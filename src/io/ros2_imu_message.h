#ifndef ACCELCAL_IO_ROS2_IMU_MESSAGE_H_
#define ACCELCAL_IO_ROS2_IMU_MESSAGE_H_

// One sensor_msgs/msg/Imu message as a ROS 2 bag stores it: serialized by the middleware in
// CDR (OMG CDR version 1, what Fast DDS and Cyclone DDS write for ROS 2, the bag's
// serialization_format "cdr"). The bytes are a 4-byte encapsulation header, 0x00 0x01 for
// little-endian CDR (0x00 0x00 big-endian, then two option bytes), and the fields in order,
// each aligned to its own size relative to the first byte after the header:
//
//   std_msgs/Header header
//     builtin_interfaces/Time stamp   int32 sec, uint32 nanosec
//     string frame_id                 uint32 length (with the closing NUL), then the bytes
//   geometry_msgs/Quaternion orientation          4 float64 (x, y, z, w)
//   float64[9] orientation_covariance
//   geometry_msgs/Vector3 angular_velocity        3 float64, rad/s (REP 145)
//   float64[9] angular_velocity_covariance
//   geometry_msgs/Vector3 linear_acceleration     3 float64, m/s^2 (REP 145)
//   float64[9] linear_acceleration_covariance
//
// Every read is bounds-checked: a message cut short, a string longer than the message, an
// encapsulation other than CDR version 1 or a value that is not finite is refused with one
// line saying which field and at what byte. EncodeRos2ImuMessage writes the same layout
// (tests write bags with it).

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "common/status.h"

namespace accelcal {

struct Ros2ImuMessage {
  int32_t stamp_sec = 0;
  uint32_t stamp_nanosec = 0;
  std::string frame_id;
  std::array<double, 4> orientation{};  // x, y, z, w
  std::array<double, 9> orientation_covariance{};
  std::array<double, 3> angular_velocity_radps{};
  std::array<double, 9> angular_velocity_covariance{};
  std::array<double, 3> linear_acceleration_mps2{};
  std::array<double, 9> linear_acceleration_covariance{};

  // The header stamp in nanoseconds (sec * 1e9 + nanosec).
  int64_t StampNs() const { return int64_t{stamp_sec} * 1000000000 + stamp_nanosec; }
};

// Decodes `data`, one message's serialized bytes. The failure says what is wrong with no
// context (callers add the file and the message's row). The values used (the two vectors) must
// be finite; the orientation and the covariances are decoded, bounds-checked and kept as they
// are (Imu.msg asks a driver that has no estimate of a field to write -1 in its covariance's first
// cell).
Status DecodeRos2ImuMessage(std::string_view data, Ros2ImuMessage* message);

// The CDR bytes of `message`, little-endian (`big_endian`: the other byte order), as a ROS 2
// middleware serializes it.
std::string EncodeRos2ImuMessage(const Ros2ImuMessage& message, bool big_endian = false);

}  // namespace accelcal

#endif  // ACCELCAL_IO_ROS2_IMU_MESSAGE_H_
