#include "io/ros2_bag.h"

#include <dirent.h>
#include <sqlite3.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>

#include "common/format.h"
#include "io/imu_log_format.h"
#include "io/input_file.h"
#include "io/input_text.h"
#include "io/ros2_imu_message.h"

namespace accelcal {
namespace {

constexpr char kImuType[] = "sensor_msgs/msg/Imu";
constexpr char kMcapMagic[] = "\x89MCAP0\r\n";
constexpr uint64_t kMaxMetadataBytes = 16ull << 20;
constexpr size_t kMaxFrameIdsKept = 4;

// A time in ns as seconds with all nine decimals ("1700000001.990000000"), exactly.
std::string SecondsText(int64_t ns) {
  const uint64_t magnitude = ns < 0 ? 0 - static_cast<uint64_t>(ns) : static_cast<uint64_t>(ns);
  return StringPrintf("%s%llu.%09llu", ns < 0 ? "-" : "",
                      static_cast<unsigned long long>(magnitude / 1000000000),
                      static_cast<unsigned long long>(magnitude % 1000000000));
}

bool IsDirectory(const std::string& path) {
  struct stat info;
  return stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode);
}

bool IsRegularFile(const std::string& path) {
  struct stat info;
  return stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

bool EndsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The first `size` bytes of a file (fewer when it is shorter; empty when it cannot be read).
std::string FileStart(const std::string& path, size_t size) {
  std::string bytes(size, '\0');
  FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return "";
  bytes.resize(std::fread(&bytes[0], 1, size, file));
  std::fclose(file);
  return bytes;
}

bool HasSqliteHeader(const std::string& path) {
  return FileStart(path, sizeof(kSqliteHeader)) ==
         std::string(kSqliteHeader, sizeof(kSqliteHeader));
}

bool IsMcap(const std::string& path) {
  return EndsWith(path, ".mcap") || FileStart(path, 8) == std::string(kMcapMagic, 8);
}

std::vector<std::string> FolderEntries(const std::string& folder) {
  std::vector<std::string> names;
  DIR* dir = opendir(folder.c_str());
  if (dir == nullptr) return names;
  while (const dirent* entry = readdir(dir)) names.push_back(entry->d_name);
  closedir(dir);
  std::sort(names.begin(), names.end());
  return names;
}

// The number after the last '_' of NAME_N.db3 (rosbag2's split files), -1 without one.
long long SplitIndex(const std::string& name) {
  const std::string stem = name.substr(0, name.size() - 4);
  const size_t underscore = stem.rfind('_');
  if (underscore == std::string::npos || underscore + 1 == stem.size()) return -1;
  long long index = 0;
  for (size_t i = underscore + 1; i < stem.size(); ++i) {
    if (stem[i] < '0' || stem[i] > '9' || index > 1000000000) return -1;
    index = index * 10 + (stem[i] - '0');
  }
  return index;
}

std::string Unquoted(std::string text) {
  if (text.size() >= 2 && (text.front() == '"' || text.front() == '\'') &&
      text.back() == text.front())
    return text.substr(1, text.size() - 2);
  return text;
}

// metadata.yaml as rosbag2 writes it (yaml-cpp's block style): the storage identifier and the
// list under relative_file_paths. Only these two keys are read.
Status ParseBagMetadata(const std::string& text, std::string* storage,
                        std::vector<std::string>* relative_paths) {
  size_t begin = 0;
  int list_indent = -1;  // the indentation of relative_file_paths:, while in its list
  while (begin < text.size()) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(begin, end - begin);
    begin = end + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const size_t first = line.find_first_not_of(' ');
    if (first == std::string::npos) continue;
    const std::string content = line.substr(first);
    const int indent = static_cast<int>(first);
    if (list_indent >= 0) {
      if (content.rfind("- ", 0) == 0 && indent >= list_indent) {
        relative_paths->push_back(Unquoted(std::string(TrimLine(content.substr(2)))));
        continue;
      }
      list_indent = -1;
    }
    if (content.rfind("storage_identifier:", 0) == 0) {
      *storage = Unquoted(std::string(TrimLine(content.substr(19))));
    } else if (content.rfind("relative_file_paths:", 0) == 0) {
      const std::string rest(TrimLine(content.substr(20)));
      if (rest == "[]") continue;
      if (!rest.empty()) {
        return Status::Error(
            "relative_file_paths is not written as rosbag2 writes it (one '- NAME' per line)");
      }
      list_indent = indent;
    }
  }
  return Status::Ok();
}

std::string Joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
  return text;
}

std::string McapRefusal() {
  return "MCAP storage is not read here (Debian 12 packages no MCAP reader): convert the bag to "
         "sqlite3 storage with `ros2 bag convert -i BAG -o out.yaml`, out.yaml holding "
         "output_bags: [{uri: BAG_sqlite, storage_id: sqlite3}], and give the new folder";
}

// The path as an SQLite URI (file:...?immutable=1): every byte but unreserved ones and '/'
// percent-encoded.
std::string ImmutableUri(const std::string& path) {
  std::string uri = "file:";
  for (unsigned char c : path) {
    if (std::isalnum(c) || c == '/' || c == '.' || c == '_' || c == '-' || c == '~') {
      uri += static_cast<char>(c);
    } else {
      uri += StringPrintf("%%%02X", c);
    }
  }
  return uri + "?immutable=1";
}

struct SqliteCloser {
  void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
struct StatementFinalizer {
  void operator()(sqlite3_stmt* statement) const { sqlite3_finalize(statement); }
};
using Database = std::unique_ptr<sqlite3, SqliteCloser>;
using Statement = std::unique_ptr<sqlite3_stmt, StatementFinalizer>;

const char kDamaged[] =
    "; the file is damaged or not a rosbag2 sqlite3 bag: record it again, or give the bag's "
    "folder as ros2 bag wrote it";

// One open storage file: the file's identity at its opening, the database read-only.
struct BagFile {
  std::string path;
  FileIdentity identity;
  Database db;
};

Status SqliteError(sqlite3* db, const std::string& what) {
  return Status::Error(what + ": SQLite says '" + (db ? sqlite3_errmsg(db) : "out of memory") +
                       "'" + kDamaged);
}

// Opens `path` as a rosbag2 storage file: the SQLite header, the size the header states, no
// write-ahead log or hot journal left beside it, the database sound (quick_check) and the
// tables topics and messages present. No file name in the messages (the caller adds it).
Status OpenBagFile(const std::string& path, BagFile* file) {
  file->path = path;
  ACCELCAL_RETURN_IF_ERROR(IdentifyFile(path, &file->identity));
  const std::string head = FileStart(path, 100);
  if (head.size() < sizeof(kSqliteHeader) ||
      head.compare(0, sizeof(kSqliteHeader), std::string(kSqliteHeader, sizeof(kSqliteHeader))) !=
          0) {
    if (IsMcap(path)) return Status::Error(McapRefusal());
    return Status::Error(
        "not an SQLite database (no 'SQLite format 3' header): a rosbag2 sqlite3 bag's .db3 file "
        "starts with one; give the bag's folder or its .db3 file");
  }
  if (head.size() < 100) {
    return Status::Error(
        StringPrintf("the file is cut short: %zu bytes, less than SQLite's 100-byte header%s",
                     head.size(), kDamaged));
  }
  auto byte = [&head](size_t i) { return static_cast<uint32_t>(static_cast<uint8_t>(head[i])); };
  uint64_t page_size = (byte(16) << 8) | byte(17);
  if (page_size == 1) page_size = 65536;
  const uint64_t page_count = (byte(28) << 24) | (byte(29) << 16) | (byte(30) << 8) | byte(31);
  const bool count_valid =
      page_count > 0 && head.compare(24, 4, head, 92, 4) == 0;  // change counter = valid-for
  if (count_valid && page_count * page_size > file->identity.size) {
    return Status::Error(StringPrintf(
        "the file is cut short: its SQLite header states %llu pages of %llu bytes (%llu bytes), "
        "the "
        "file has %llu; copy the bag again from where it was recorded",
        static_cast<unsigned long long>(page_count), static_cast<unsigned long long>(page_size),
        static_cast<unsigned long long>(page_count * page_size),
        static_cast<unsigned long long>(file->identity.size)));
  }
  for (const char* suffix : {"-wal", "-journal"}) {
    struct stat info;
    if (stat((path + suffix).c_str(), &info) == 0 && info.st_size > 0) {
      return Status::Error(
          std::string("the bag was not closed: ") + path + suffix +
          " beside it holds writes not yet in it; let the recorder finish, or open the file once "
          "with the sqlite3 command (which merges them) before reading it");
    }
  }
  sqlite3* db = nullptr;
  const int opened = sqlite3_open_v2(ImmutableUri(path).c_str(), &db,
                                     SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr);
  file->db.reset(db);
  if (opened != SQLITE_OK) return SqliteError(db, "cannot be opened");
  sqlite3_extended_result_codes(db, 1);
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v2(db, "PRAGMA quick_check(1)", -1, &raw, nullptr) != SQLITE_OK)
    return SqliteError(db, "its integrity cannot be checked");
  Statement check(raw);
  const int step = sqlite3_step(check.get());
  if (step != SQLITE_ROW) return SqliteError(db, "its integrity cannot be checked");
  const char* verdict = reinterpret_cast<const char*>(sqlite3_column_text(check.get(), 0));
  if (verdict == nullptr || std::strcmp(verdict, "ok") != 0) {
    return Status::Error(std::string("the SQLite database is damaged (quick_check: ") +
                         EchoInput(verdict ? verdict : "no answer") + ")" + kDamaged);
  }
  for (const char* table : {"topics", "messages"}) {
    const std::string query =
        std::string("SELECT count(*) FROM sqlite_master WHERE type='table' AND name='") + table +
        "'";
    if (sqlite3_prepare_v2(db, query.c_str(), -1, &raw, nullptr) != SQLITE_OK)
      return SqliteError(db, "its tables cannot be listed");
    Statement count(raw);
    if (sqlite3_step(count.get()) != SQLITE_ROW)
      return SqliteError(db, "its tables cannot be listed");
    if (sqlite3_column_int64(count.get(), 0) == 0) {
      return Status::Error(std::string("an SQLite database without the table '") + table +
                           "' of rosbag2's sqlite3 storage: not a ROS 2 bag; give the bag's .db3 "
                           "file or its folder");
    }
  }
  return Status::Ok();
}

Status Prepare(const BagFile& file, const char* query, Statement* statement) {
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v2(file.db.get(), query, -1, &raw, nullptr) != SQLITE_OK) {
    Statement failed(raw);
    return SqliteError(file.db.get(),
                       "the query of rosbag2's tables topics(id, name, type, "
                       "serialization_format) and messages(id, topic_id, "
                       "timestamp, data) fails");
  }
  statement->reset(raw);
  return Status::Ok();
}

std::string ColumnText(sqlite3_stmt* statement, int column) {
  const unsigned char* text = sqlite3_column_text(statement, column);
  return text == nullptr ? std::string() : reinterpret_cast<const char*>(text);
}

Status TopicsOf(const BagFile& file, std::vector<Ros2BagTopic>* topics) {
  Statement statement;
  ACCELCAL_RETURN_IF_ERROR(Prepare(file,
                                   "SELECT t.name, t.type, t.serialization_format, "
                                   "(SELECT count(*) FROM messages m WHERE m.topic_id = t.id) "
                                   "FROM topics t ORDER BY t.id",
                                   &statement));
  int step;
  while ((step = sqlite3_step(statement.get())) == SQLITE_ROW) {
    Ros2BagTopic topic;
    topic.name = ColumnText(statement.get(), 0);
    topic.type = ColumnText(statement.get(), 1);
    topic.serialization_format = ColumnText(statement.get(), 2);
    topic.message_count = sqlite3_column_int64(statement.get(), 3);
    topics->push_back(std::move(topic));
  }
  if (step != SQLITE_DONE) return SqliteError(file.db.get(), "its topics cannot be read");
  return Status::Ok();
}

// The topics of every file, merged by name (their types must agree).
Status MergeTopics(const std::vector<BagFile>& files, std::vector<Ros2BagTopic>* topics) {
  topics->clear();
  for (const BagFile& file : files) {
    std::vector<Ros2BagTopic> own;
    ACCELCAL_RETURN_IF_ERROR(TopicsOf(file, &own).WithContext(file.path));
    for (const Ros2BagTopic& topic : own) {
      auto same = std::find_if(topics->begin(), topics->end(),
                               [&topic](const Ros2BagTopic& t) { return t.name == topic.name; });
      if (same == topics->end()) {
        topics->push_back(topic);
      } else if (same->type != topic.type) {
        return Status::Error(file.path + ": topic '" + EchoInput(topic.name) + "' is of type " +
                             EchoInput(topic.type) + ", " + EchoInput(same->type) +
                             " in the bag's earlier files; a bag's topic has one type");
      } else {
        same->message_count += topic.message_count;
      }
    }
  }
  return Status::Ok();
}

std::string TopicListing(const std::vector<Ros2BagTopic>& topics) {
  if (topics.empty()) return "none";
  std::string text;
  for (const Ros2BagTopic& topic : topics)
    text += (text.empty() ? "" : ", ") + EchoInput(topic.name) + " (" + EchoInput(topic.type) + ")";
  return text;
}

// The topic to read, by --topic or as the bag's one Imu topic.
Status ChooseTopic(const std::string& bag, const std::vector<Ros2BagTopic>& topics,
                   const std::string& wanted, Ros2BagTopic* chosen, std::string* note) {
  std::vector<Ros2BagTopic> imu;
  for (const Ros2BagTopic& topic : topics)
    if (topic.type == kImuType) imu.push_back(topic);
  if (!wanted.empty()) {
    auto it = std::find_if(topics.begin(), topics.end(),
                           [&wanted](const Ros2BagTopic& t) { return t.name == wanted; });
    if (it == topics.end()) {
      return Status::Error(bag + ": --topic=" + EchoInput(wanted) +
                           " is not in the bag; its topics: " + TopicListing(topics));
    }
    if (it->type != kImuType) {
      std::vector<std::string> names;
      for (const Ros2BagTopic& topic : imu) names.push_back(EchoInput(topic.name));
      return Status::Error(bag + ": --topic=" + EchoInput(wanted) + " is of type " +
                           EchoInput(it->type) + ", not sensor_msgs/msg/Imu; " +
                           (imu.empty() ? std::string("the bag has no Imu topic")
                                        : "its Imu topics: " + Joined(names)));
    }
    *chosen = *it;
    return Status::Ok();
  }
  if (imu.size() == 1) {
    *chosen = imu[0];
    *note = "topic " + EchoInput(chosen->name) +
            " read: the bag's one sensor_msgs/msg/Imu topic (--topic names another)";
    return Status::Ok();
  }
  if (imu.empty()) {
    return Status::Error(
        bag + ": no sensor_msgs/msg/Imu topic in the bag; its topics: " + TopicListing(topics) +
        "; record the IMU driver's Imu topic, or convert its messages");
  }
  std::vector<std::string> names;
  for (const Ros2BagTopic& topic : imu) names.push_back(EchoInput(topic.name));
  return Status::Error(bag + ": " + std::to_string(imu.size()) + " sensor_msgs/msg/Imu topics (" +
                       Joined(names) + "): name one with --topic=" + names[0] +
                       " (one IMU per calibration)");
}

// The file as a run reads it: unchanged since its opening, and recorded for the provenance.
Status RecordRead(const BagFile& file) {
  FileIdentity now;
  ACCELCAL_RETURN_IF_ERROR(IdentifyFile(file.path, &now));
  if (now != file.identity) return FileChangedWhileRead(file.identity, now);
  if (!RecordingInputReads()) return Status::Ok();
  InputRead read;
  ACCELCAL_RETURN_IF_ERROR(HashFile(file.path, &read));
  if (read.identity != file.identity) return FileChangedWhileRead(file.identity, read.identity);
  return RecordInputRead(file.path, read);
}

}  // namespace

bool IsRos2Bag(const std::string& path) {
  if (IsDirectory(path)) {
    for (const std::string& name : FolderEntries(path))
      if (name == "metadata.yaml" || EndsWith(name, ".db3") || EndsWith(name, ".mcap")) return true;
    return false;
  }
  return IsRegularFile(path) && (HasSqliteHeader(path) || IsMcap(path));
}

Status ListRos2BagFiles(const std::string& path, std::vector<std::string>* files,
                        std::string* metadata_path) {
  files->clear();
  metadata_path->clear();
  if (!IsDirectory(path)) {
    if (IsMcap(path)) return Status::Error(path + ": " + McapRefusal());
    files->push_back(path);
    return Status::Ok();
  }
  const std::string folder = EndsWith(path, "/") ? path : path + "/";
  const std::string metadata = folder + "metadata.yaml";
  if (IsRegularFile(metadata)) {
    std::string text;
    ACCELCAL_RETURN_IF_ERROR(
        ReadInputText(metadata, kMaxMetadataBytes, "a bag's metadata.yaml", &text)
            .WithContext(metadata));
    std::string storage;
    std::vector<std::string> relative;
    ACCELCAL_RETURN_IF_ERROR(ParseBagMetadata(text, &storage, &relative).WithContext(metadata));
    if (storage == "mcap") return Status::Error(metadata + ": " + McapRefusal());
    if (!storage.empty() && storage != "sqlite3") {
      return Status::Error(metadata + ": storage '" + EchoInput(storage) +
                           "' is not rosbag2's sqlite3; convert the bag with `ros2 bag convert` "
                           "to storage_id sqlite3");
    }
    if (relative.empty()) {
      return Status::Error(metadata +
                           ": no relative_file_paths: the bag lists no storage file; give the "
                           ".db3 file itself, or run `ros2 bag reindex` on the folder");
    }
    for (const std::string& name : relative) {
      if (EndsWith(name, ".zstd")) {
        return Status::Error(metadata + ": the bag is compressed (" + EchoInput(name) +
                             "); decompress it with `ros2 bag decompress` (or `ros2 bag convert` "
                             "without compression) and give the new folder");
      }
      const std::string file = name.empty() || name[0] == '/' ? name : folder + name;
      if (!IsRegularFile(file)) {
        return Status::Error(metadata + ": it lists '" + EchoInput(name) +
                             "', which is not a file of the folder; copy the whole bag folder");
      }
      files->push_back(file);
    }
    *metadata_path = metadata;
    return Status::Ok();
  }
  std::vector<std::pair<long long, std::string>> found;
  bool mcap = false;
  for (const std::string& name : FolderEntries(folder)) {
    if (EndsWith(name, ".mcap")) mcap = true;
    if (EndsWith(name, ".db3")) found.push_back({SplitIndex(name), name});
  }
  if (found.empty()) {
    if (mcap) return Status::Error(path + ": " + McapRefusal());
    return Status::Error(path +
                         ": a folder with neither metadata.yaml nor a .db3 file: not a "
                         "ROS 2 bag in sqlite3 storage");
  }
  std::sort(found.begin(), found.end());
  for (const auto& [index, name] : found) files->push_back(folder + name);
  return Status::Ok();
}

Status ListRos2BagTopics(const std::vector<std::string>& paths, std::vector<Ros2BagTopic>* topics) {
  std::vector<BagFile> files(paths.size());
  for (size_t i = 0; i < paths.size(); ++i)
    ACCELCAL_RETURN_IF_ERROR(OpenBagFile(paths[i], &files[i]).WithContext(paths[i]));
  return MergeTopics(files, topics);
}

bool ParseRos2BagTime(const std::string& text, Ros2BagTime* time) {
  if (text == "header") {
    *time = Ros2BagTime::kHeaderStamp;
  } else if (text == "receive") {
    *time = Ros2BagTime::kReceive;
  } else {
    return false;
  }
  return true;
}

Status ReadRos2BagImuLog(const std::string& path, const Ros2BagReadOptions& options, TriadLog* log,
                         Ros2BagSource* source) {
  *log = TriadLog();
  *source = Ros2BagSource();
  std::vector<std::string> paths;
  std::string metadata;
  ACCELCAL_RETURN_IF_ERROR(ListRos2BagFiles(path, &paths, &metadata));
  std::vector<BagFile> files(paths.size());
  for (size_t i = 0; i < paths.size(); ++i)
    ACCELCAL_RETURN_IF_ERROR(OpenBagFile(paths[i], &files[i]).WithContext(paths[i]));
  std::vector<Ros2BagTopic> topics;
  ACCELCAL_RETURN_IF_ERROR(MergeTopics(files, &topics));
  Ros2BagTopic topic;
  std::string note;
  ACCELCAL_RETURN_IF_ERROR(ChooseTopic(path, topics, options.topic, &topic, &note));
  if (topic.serialization_format != "cdr") {
    return Status::Error(path + ": topic " + EchoInput(topic.name) + " is serialized as '" +
                         EchoInput(topic.serialization_format) +
                         "', not 'cdr'; convert the bag with `ros2 bag convert` to cdr");
  }
  const bool header_time = options.time == Ros2BagTime::kHeaderStamp;
  int64_t first_ns = 0;
  int64_t previous_ns = 0;
  size_t count = 0;
  // Messages whose angular_velocity_covariance[0] is -1: sensor_msgs/msg/Imu's mark of "no
  // estimate of this element" (an accelerometer-only driver's zeros).
  size_t without_rates = 0;
  for (const BagFile& file : files) {
    Statement statement;
    ACCELCAL_RETURN_IF_ERROR(Prepare(file,
                                     "SELECT m.id, m.timestamp, m.data FROM messages m JOIN topics "
                                     "t ON m.topic_id = t.id WHERE t.name = ?1 "
                                     "ORDER BY m.timestamp, m.id",
                                     &statement)
                                 .WithContext(file.path));
    sqlite3_bind_text(statement.get(), 1, topic.name.c_str(), -1, SQLITE_TRANSIENT);
    int step;
    while ((step = sqlite3_step(statement.get())) == SQLITE_ROW) {
      const int64_t id = sqlite3_column_int64(statement.get(), 0);
      const int64_t receive_ns = sqlite3_column_int64(statement.get(), 1);
      const void* blob = sqlite3_column_blob(statement.get(), 2);
      const int bytes = sqlite3_column_bytes(statement.get(), 2);
      const std::string where =
          StringPrintf("%s: message id %lld (topic %s)", file.path.c_str(),
                       static_cast<long long>(id), EchoInput(topic.name).c_str());
      if (sqlite3_column_type(statement.get(), 1) != SQLITE_INTEGER) {
        return Status::Error(where + ": its timestamp is not an integer (ns)" + kDamaged);
      }
      Ros2ImuMessage message;
      const Status decoded = DecodeRos2ImuMessage(
          std::string_view(static_cast<const char*>(blob), blob ? static_cast<size_t>(bytes) : 0),
          &message);
      if (!decoded.ok()) {
        return Status::Error(where + ": " + decoded.message() +
                             "; the bag is damaged, or the topic is not sensor_msgs/msg/Imu "
                             "as ROS 2 serializes it");
      }
      const int64_t t_ns = header_time ? message.StampNs() : receive_ns;
      if (count == 0) first_ns = t_ns;
      if (count > 0 && t_ns <= previous_ns) {
        return Status::Error(StringPrintf(
            "%s: its %s %s s does not increase from the previous message's %s s; a log's time "
            "must be strictly increasing%s",
            where.c_str(), header_time ? "header stamp" : "receive time", SecondsText(t_ns).c_str(),
            SecondsText(previous_ns).c_str(),
            header_time ? " (give --bag_time=receive to time the samples by the bag's receive "
                          "times, if the driver's stamps are wrong)"
                        : ""));
      }
      previous_ns = t_ns;
      ++count;
      log->timestamp_s.push_back(static_cast<double>(t_ns - first_ns) * 1e-9);
      log->output.push_back(message.linear_acceleration_mps2);
      log->gyroscope.push_back(message.angular_velocity_radps);
      if (message.angular_velocity_covariance[0] == -1.0) ++without_rates;
      if (source->frame_ids.size() < kMaxFrameIdsKept &&
          std::find(source->frame_ids.begin(), source->frame_ids.end(), message.frame_id) ==
              source->frame_ids.end())
        source->frame_ids.push_back(message.frame_id);
    }
    if (step != SQLITE_DONE)
      return SqliteError(file.db.get(), "its messages cannot be read").WithContext(file.path);
    ACCELCAL_RETURN_IF_ERROR(RecordRead(file).WithContext(file.path));
  }
  if (count == 0) {
    return Status::Error(path + ": topic " + EchoInput(topic.name) +
                         " holds no messages; record the IMU again");
  }
  if (without_rates == count) {
    log->gyroscope.clear();
    source->notes.push_back(
        "gyroscope: none: every message's angular_velocity_covariance[0] is -1, sensor_msgs/msg/"
        "Imu's mark of no angular velocity data (an accelerometer-only driver); the accelerometer "
        "alone is read");
  }
  if (!metadata.empty()) source->files.push_back(metadata);
  source->files.insert(source->files.end(), paths.begin(), paths.end());
  if (IsDirectory(path)) {
    std::vector<InputFolderPart> parts;
    for (size_t i = 0; i < paths.size(); ++i)
      parts.push_back({i == 0 ? "" : "_part_" + std::to_string(i + 1), paths[i]});
    if (!metadata.empty()) parts.push_back({"_metadata", metadata});
    RecordInputFolder(path, parts);
  }
  source->topic = topic.name;
  source->layout = StringPrintf(
      "ROS 2 bag (sqlite3, %zu file%s; topic %s, sensor_msgs/msg/Imu in CDR, %zu messages: "
      "linear_acceleration in m/s^2, angular_velocity in rad/s)",
      paths.size(), paths.size() == 1 ? "" : "s", EchoInput(topic.name).c_str(), count);
  if (!note.empty()) source->notes.push_back(note);
  source->notes.push_back(StringPrintf(
      "time: the messages' %s, counted from the first message's (%s s)",
      header_time ? "header stamps (sec + nanosec; --bag_time=receive for the bag's receive times)"
                  : "receive times in the bag (--bag_time=receive)",
      SecondsText(first_ns).c_str()));
  std::vector<std::string> frames;
  for (const std::string& frame : source->frame_ids) frames.push_back("'" + EchoInput(frame) + "'");
  source->notes.push_back("frame_id " + Joined(frames) +
                          "; the orientation and covariances of the messages are not used");
  return Status::Ok();
}

}  // namespace accelcal
