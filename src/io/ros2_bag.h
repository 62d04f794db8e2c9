#ifndef ACCELCAL_IO_ROS2_BAG_H_
#define ACCELCAL_IO_ROS2_BAG_H_

// A ROS 2 bag in rosbag2's sqlite3 storage, read through Debian's SQLite library: the IMU's
// sensor_msgs/msg/Imu messages of one topic as a three-axis log (common/triad_log.h), the
// accelerometer's linear_acceleration in m/s^2 and the gyroscope's angular_velocity in rad/s
// (REP 145), decoded by io/ros2_imu_message.h.
//
// A bag is a folder holding metadata.yaml and its storage files NAME_0.db3, NAME_1.db3, ...
// (a split bag: read in the order metadata.yaml's relative_file_paths lists them; without
// metadata.yaml, every .db3 of the folder in the order of its _N suffix), or one .db3 file
// given by itself. Each .db3 holds the tables rosbag2 writes:
//   topics(id, name, type, serialization_format, offered_qos_profiles[, type_description_hash])
//   messages(id, topic_id, timestamp, data)       timestamp: the recorder's receive time, ns
// (and, since rosbag2's schema 3, schema, metadata and message_definitions, not needed here).
// Messages are read in rosbag2's own order, by receive time then id, file after file.
//
// The topic: the one named (--topic), which must be a sensor_msgs/msg/Imu topic in 'cdr'; else
// the bag's one Imu topic, said so in a note; several, or none, are refused listing them.
// Time: the messages' header stamps (sec + nanosec, the driver's sample times) by default, or the
// bag's receive times (--bag_time=receive), counted from the first message in whole ns; either
// must increase strictly from message to message, as a text log's time must.
// MCAP storage (rosbag2's default since Iron) is refused with the command that converts it: no
// MCAP reader is packaged by Debian 12. So is a compressed bag (.db3.zstd).
//
// Every failure is one line starting with the file it concerns: what is wrong and what to do.
// The files are opened read-only and immutable (SQLite writes nothing beside them), must be
// unchanged from their opening to the end of the reading, and are recorded for the run's
// provenance (io/input_file.h, RecordInputRead) as the .mat reader records its file.

#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "common/triad_log.h"

namespace accelcal {

// The first bytes of every SQLite 3 database file.
constexpr char kSqliteHeader[] = "SQLite format 3";  // and a NUL: 16 bytes

// Whether `path` is to be read as a ROS 2 bag: a folder holding metadata.yaml or a .db3 file,
// a file that starts with SQLite's header, or an MCAP file (by its magic or its .mcap suffix,
// which ReadRos2BagImuLog refuses with the conversion to sqlite3).
bool IsRos2Bag(const std::string& path);

struct Ros2BagTopic {
  std::string name;
  std::string type;  // "sensor_msgs/msg/Imu"
  std::string serialization_format;
  int64_t message_count = 0;
};

// The storage files of the bag at `path` (a folder or a .db3 file), in reading order, and the
// metadata.yaml read, if any.
Status ListRos2BagFiles(const std::string& path, std::vector<std::string>* files,
                        std::string* metadata_path);

// The topics of the bag's files, by first appearance, with their messages counted over all files.
Status ListRos2BagTopics(const std::vector<std::string>& files, std::vector<Ros2BagTopic>* topics);

enum class Ros2BagTime { kHeaderStamp, kReceive };

// "header" or "receive" (--bag_time); false for another text.
bool ParseRos2BagTime(const std::string& text, Ros2BagTime* time);

struct Ros2BagReadOptions {
  std::string topic;  // empty: the bag's one Imu topic
  Ros2BagTime time = Ros2BagTime::kHeaderStamp;
};

// What was read, for the report and the provenance.
struct Ros2BagSource {
  std::string layout;              // one line: storage, topic, type, messages, time
  std::vector<std::string> notes;  // the choices made, sentences to print
  std::vector<std::string> files;  // every file read: metadata.yaml first, then the .db3 files
  std::string topic;
  std::vector<std::string> frame_ids;  // the header frame_ids seen (at most a few)
};

// The messages of the chosen topic as a log: time in s from the first message, output the
// linear acceleration (m/s^2), gyroscope the angular velocity (rad/s). Failures start with the
// file they concern.
Status ReadRos2BagImuLog(const std::string& path, const Ros2BagReadOptions& options, TriadLog* log,
                         Ros2BagSource* source);

}  // namespace accelcal

#endif  // ACCELCAL_IO_ROS2_BAG_H_
