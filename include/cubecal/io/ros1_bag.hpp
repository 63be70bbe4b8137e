/// @file
/// ROS 1 bag files (format 2.0), read without a ROS install: the connections
/// (topic, message type) and every message's serialized bytes, from chunks
/// stored uncompressed or compressed with bz2 or LZ4 (the LZ4 frame format
/// roslz4 writes). Index records are only counted, never needed: a bag whose
/// index was never written (a recording that was killed) reads the same.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal::io {

/// "#ROSBAG V2.0\n", the first bytes of every ROS 1 bag.
inline constexpr std::string_view kRos1BagMagic = "#ROSBAG V2.0\n";

/// Whether `head` (the first bytes of a file) starts like a ROS bag of any
/// version ("#ROSBAG V"); read_ros1_bag refuses versions other than 2.0.
bool looks_like_ros_bag(std::string_view head) noexcept;

/// A connection of a ROS 1 bag: a topic with its message type.
struct Ros1Connection {
  /// The connection's id in the bag.
  std::uint32_t id = 0;
  /// The topic's name, "/imu/data_raw".
  std::string topic;
  std::string type;  ///< "sensor_msgs/Imu"
  /// The MD5 sum of the message definition, as the bag gives it.
  std::string md5sum;
  std::size_t messages = 0;  ///< message records read
  std::size_t indexed = 0;   ///< messages the bag's index records count
};

/// One message record of a ROS 1 bag.
struct Ros1Message {
  std::uint32_t connection = 0;  ///< Ros1Connection::id
  std::uint32_t sec = 0;         ///< record time: when the bag recorded it
  /// Nanoseconds of the record time, added to sec.
  std::uint32_t nsec = 0;
  std::size_t offset = 0;   ///< byte offset of its record in the file, or of its chunk when compressed
  bool compressed = false;  ///< read from a compressed chunk (offset is the chunk's)
  std::size_t begin = 0;    ///< the serialized message: Ros1Bag::payload[begin, begin + size)
  /// Bytes of the serialized message.
  std::size_t size = 0;
};

/// A ROS 1 bag (format 2.0) read whole: connections and messages.
struct Ros1Bag {
  /// The path given.
  std::string file;
  std::vector<Ros1Connection> connections;  ///< in the order first seen
  std::vector<Ros1Message> messages;        ///< in file order
  std::string payload;                      ///< every message's bytes, concatenated
  /// The serialized bytes of message `m` (a view into payload). Throws nothing.
  std::string_view data(const Ros1Message& m) const noexcept {
    return std::string_view(payload).substr(m.begin, m.size);
  }
  /// The connection with id `id`, or null when the bag has none. Throws nothing.
  const Ros1Connection* connection(std::uint32_t id) const noexcept;
};

/// Parses a whole bag held in memory. Every length is checked against the
/// bytes there are: a truncated or corrupt bag, an unknown chunk compression
/// or a message on an undeclared connection is an InputError naming `file`
/// and the byte offset ("FILE: byte 1234: ...").
Ros1Bag parse_ros1_bag(std::string_view bytes, const std::string& file);

/// The same from a file (memory-mapped).
Ros1Bag read_ros1_bag(const std::string& path);

}  // namespace cubecal::io
