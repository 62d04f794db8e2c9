// libFuzzer target: a ROS 2 bag's sensor_msgs/msg/Imu message (io/ros2_imu_message.h) decoded
// from arbitrary bytes, as io/ros2_bag.cc decodes every message of the chosen topic. It must
// return a Status for every input, never read past the bytes; a message it accepts must hold
// finite vectors and a valid stamp, and decode again to itself once re-encoded.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "io/ros2_imu_message.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  accelcal::Ros2ImuMessage message;
  if (!accelcal::DecodeRos2ImuMessage(std::string_view(reinterpret_cast<const char*>(data), size),
                                      &message)
           .ok())
    return 0;
  if (message.stamp_nanosec >= 1000000000u) std::abort();
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(message.linear_acceleration_mps2[k])) std::abort();
    if (!std::isfinite(message.angular_velocity_radps[k])) std::abort();
  }
  accelcal::Ros2ImuMessage again;
  const bool big_endian = size > 1 && data[1] == 0;
  if (!accelcal::DecodeRos2ImuMessage(accelcal::EncodeRos2ImuMessage(message, big_endian), &again)
           .ok())
    std::abort();
  if (again.frame_id != message.frame_id || again.StampNs() != message.StampNs() ||
      again.linear_acceleration_mps2 != message.linear_acceleration_mps2 ||
      again.angular_velocity_radps != message.angular_velocity_radps)
    std::abort();
  return 0;
}
