/// @file
/// The messages of a robot log, whatever its container (ROS 1 bag, MCAP,
/// rosbag2 SQLite): topics with their message type and serialization, and
/// every message's log time and serialized bytes. The sensor-message
/// decoding, topic choice and timing of read_series work on this.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal::io {

struct Ros1Bag;

/// A topic of a message log.
struct LogTopic {
  std::string name;          ///< "/imu/data_raw"
  std::string type;          ///< as the log names it: "sensor_msgs/Imu" (ROS 1), "sensor_msgs/msg/Imu" (ROS 2)
  std::string encoding;      ///< serialization: "ros1", "cdr", or what the log says
  std::size_t messages = 0;  ///< messages read
  std::optional<std::size_t> counted;  ///< what the log's own index or statistics count, when it has them
  std::string described() const;       ///< "/imu/data_raw (sensor_msgs/Imu, 13964 messages)"
};

/// Where a message sits, for errors.
enum class MessagePlace : std::uint8_t {
  byte,   ///< its record starts at byte `offset` of the file
  chunk,  ///< it is in the compressed chunk at byte `offset`
  row,    ///< row id `offset` of an SQLite messages table
};

/// One message of a log: its topic, place and log time, and where its bytes are.
struct LogMessage {
  std::uint32_t topic = 0;  ///< index into MessageLog::topics
  std::uint32_t part = 0;   ///< index into MessageLog::parts (a bag directory's files)
  /// Where the message sits (see MessagePlace).
  MessagePlace place = MessagePlace::byte;
  /// The byte offset or row id the place refers to.
  std::uint64_t offset = 0;
  std::int64_t sec = 0;  ///< log time: when the log recorded the message
  /// Nanoseconds of the log time, added to sec.
  std::uint32_t nsec = 0;
  std::size_t begin = 0;  ///< the serialized message: MessageLog::payload[begin, begin + size)
  /// Bytes of the serialized message.
  std::size_t size = 0;
};

/// A log of serialized messages (a ROS 1 bag, an MCAP file, a rosbag2 database or directory) in one format-neutral
/// form.
struct MessageLog {
  std::string file;                  ///< the path given (a file, or a bag directory)
  std::vector<std::string> parts;    ///< a directory's files, in the order read; empty for a single file
  std::vector<LogTopic> topics;      ///< in the order first declared
  std::vector<LogMessage> messages;  ///< in the order read
  std::string payload;               ///< every message's bytes, concatenated

  /// The serialized bytes of message `m` (a view into payload). Throws nothing.
  std::string_view data(const LogMessage& m) const noexcept {
    return std::string_view(payload).substr(m.begin, m.size);
  }
  /// "at byte 1234", "in the chunk at byte 80", "row 17 of x_0.db3".
  std::string where(const LogMessage& m) const;
  /// The index of topic `name`, added with `type` and `encoding` if new.
  /// Throws InputError(file) when it is there with another type or encoding.
  std::uint32_t topic(const std::string& name, const std::string& type, const std::string& encoding);
  /// Appends `other`'s topics (merged by name) and messages, as part `part_name`.
  void append(MessageLog&& other, const std::string& part_name);
};

/// About the bytes reading the robot log at `path` whole takes: the file
/// and its messages decompressed (a ROS 1 bag's or MCAP file's chunk sizes,
/// read from the record headers without the chunks), or a .db3's or bag
/// directory's files; 0 when `path` is no robot log. Throws nothing.
std::size_t message_log_bytes(const std::string& path) noexcept;

/// A ROS 1 bag's connections as topics (merged by topic name), its messages
/// as log messages ("ros1" serialization).
MessageLog message_log(Ros1Bag&& bag);

}  // namespace cubecal::io
