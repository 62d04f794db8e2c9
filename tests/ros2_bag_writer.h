#ifndef ACCELCAL_TESTS_ROS2_BAG_WRITER_H_
#define ACCELCAL_TESTS_ROS2_BAG_WRITER_H_

// Writes small ROS 2 bags for the tests, independently of io/ros2_bag.cc: an SQLite file with
// the tables rosbag2's sqlite3 storage creates (schema version 4: schema, metadata, topics with
// type_description_hash, message_definitions, messages and its timestamp index; or version 2's
// topics and messages only), the messages given as bytes, and the folder's metadata.yaml as
// rosbag2 writes it.

#include <sqlite3.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "common/triad_log.h"
#include "io/ros2_imu_message.h"

namespace accelcal {
namespace testing {

struct BagMessage {
  int64_t receive_ns = 0;
  std::string data;
};

struct BagTopic {
  std::string name;
  std::string type = "sensor_msgs/msg/Imu";
  std::string serialization_format = "cdr";
  std::vector<BagMessage> messages;
};

// Runs `sql`; false (and the message in `error`) when SQLite refuses it.
inline bool ExecuteSql(sqlite3* db, const std::string& sql, std::string* error) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message) == SQLITE_OK) return true;
  *error = message ? message : "sqlite3_exec failed";
  sqlite3_free(message);
  return false;
}

// Writes `topics` into a new file `path`; `modern`: rosbag2's schema 4 (Jazzy), else the
// two tables of its first releases. Returns "" or what failed.
inline std::string WriteBagFile(const std::string& path, const std::vector<BagTopic>& topics,
                                bool modern = true) {
  sqlite3* db = nullptr;
  if (sqlite3_open(path.c_str(), &db) != SQLITE_OK) {
    sqlite3_close(db);
    return "cannot create " + path;
  }
  std::string error;
  std::string schema =
      "PRAGMA journal_mode=MEMORY; BEGIN;"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, "
      "timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
      "CREATE INDEX timestamp_idx ON messages (timestamp ASC);";
  if (modern) {
    schema +=
        "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
        "INSERT INTO schema VALUES (4, 'jazzy');"
        "CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL, "
        "metadata TEXT NOT NULL);"
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
        "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL, "
        "type_description_hash TEXT NOT NULL);"
        "CREATE TABLE message_definitions(id INTEGER PRIMARY KEY, topic_type TEXT NOT NULL, "
        "encoding TEXT NOT NULL, encoded_message_definition TEXT NOT NULL, "
        "type_description_hash TEXT NOT NULL);";
  } else {
    schema +=
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
        "serialization_format TEXT NOT NULL);";
  }
  bool ok = ExecuteSql(db, schema, &error);
  for (size_t t = 0; ok && t < topics.size(); ++t) {
    const BagTopic& topic = topics[t];
    const std::string insert =
        modern ? "INSERT INTO topics VALUES (?1, ?2, ?3, ?4, '- history: 3\n  depth: 0\n', "
                 "'RIHS01_0000')"
               : "INSERT INTO topics VALUES (?1, ?2, ?3, ?4)";
    sqlite3_stmt* statement = nullptr;
    ok = sqlite3_prepare_v2(db, insert.c_str(), -1, &statement, nullptr) == SQLITE_OK;
    if (ok) {
      sqlite3_bind_int64(statement, 1, static_cast<int64_t>(t + 1));
      sqlite3_bind_text(statement, 2, topic.name.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(statement, 3, topic.type.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(statement, 4, topic.serialization_format.c_str(), -1, SQLITE_TRANSIENT);
      ok = sqlite3_step(statement) == SQLITE_DONE;
    }
    sqlite3_finalize(statement);
  }
  // Messages interleaved by receive time, as a recorder writes them.
  sqlite3_stmt* statement = nullptr;
  ok = ok && sqlite3_prepare_v2(
                 db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?1, ?2, ?3)", -1,
                 &statement, nullptr) == SQLITE_OK;
  std::vector<size_t> next(topics.size(), 0);
  while (ok) {
    int best = -1;
    for (size_t t = 0; t < topics.size(); ++t) {
      if (next[t] < topics[t].messages.size() &&
          (best < 0 ||
           topics[t].messages[next[t]].receive_ns < topics[best].messages[next[best]].receive_ns))
        best = static_cast<int>(t);
    }
    if (best < 0) break;
    const BagMessage& message = topics[best].messages[next[best]++];
    sqlite3_bind_int64(statement, 1, best + 1);
    sqlite3_bind_int64(statement, 2, message.receive_ns);
    sqlite3_bind_blob(statement, 3, message.data.data(), static_cast<int>(message.data.size()),
                      SQLITE_TRANSIENT);
    ok = sqlite3_step(statement) == SQLITE_DONE;
    sqlite3_reset(statement);
  }
  sqlite3_finalize(statement);
  if (ok) ok = ExecuteSql(db, "COMMIT;", &error);
  if (!ok && error.empty()) error = sqlite3_errmsg(db);
  sqlite3_close(db);
  return ok ? "" : path + ": " + error;
}

// metadata.yaml as rosbag2 writes it, listing `files` (names in the folder).
inline std::string BagMetadataYaml(const std::vector<std::string>& files,
                                   const std::string& storage = "sqlite3") {
  std::string text =
      "rosbag2_bagfile_information:\n"
      "  version: 9\n"
      "  storage_identifier: " +
      storage +
      "\n"
      "  duration:\n"
      "    nanoseconds: 0\n"
      "  topics_with_message_count:\n"
      "    - topic_metadata:\n"
      "        name: /imu/data\n"
      "        type: sensor_msgs/msg/Imu\n"
      "        serialization_format: cdr\n"
      "      message_count: 0\n"
      "  compression_format: \"\"\n"
      "  compression_mode: \"\"\n"
      "  relative_file_paths:\n";
  for (const std::string& file : files) text += "    - " + file + "\n";
  text += "  files:\n";
  for (const std::string& file : files) text += "    - path: " + file + "\n";
  return text;
}

// A log's samples as Imu messages: header stamps from `start_sec` plus the sample's time
// (in whole ns), received `latency_ns` later; linear_acceleration the outputs, angular_velocity
// the gyroscope's (zeros without one).
inline std::vector<BagMessage> ImuMessages(const TriadLog& log, int32_t start_sec,
                                           int64_t latency_ns = 2000000,
                                           const std::string& frame_id = "imu0") {
  std::vector<BagMessage> messages;
  for (size_t i = 0; i < log.size(); ++i) {
    const int64_t t_ns = static_cast<int64_t>(std::llround(log.timestamp_s[i] * 1e9));
    Ros2ImuMessage message;
    message.stamp_sec = start_sec + static_cast<int32_t>(t_ns / 1000000000);
    message.stamp_nanosec = static_cast<uint32_t>(t_ns % 1000000000);
    message.frame_id = frame_id;
    message.orientation = {0.0, 0.0, 0.0, 1.0};
    message.orientation_covariance[0] = -1.0;
    message.linear_acceleration_mps2 = log.output[i];
    if (log.has_gyroscope()) {
      message.angular_velocity_radps = log.gyroscope[i];
    } else {
      message.angular_velocity_covariance[0] = -1.0;  // an accelerometer-only driver's mark
    }
    messages.push_back(
        {int64_t{start_sec} * 1000000000 + t_ns + latency_ns, EncodeRos2ImuMessage(message)});
  }
  return messages;
}

}  // namespace testing
}  // namespace accelcal

#endif  // ACCELCAL_TESTS_ROS2_BAG_WRITER_H_
