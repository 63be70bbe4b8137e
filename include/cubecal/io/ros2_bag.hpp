/// @file
/// ROS 2 bags (rosbag2), read without a ROS install: an SQLite .db3 file
/// (tables topics(id, name, type, serialization_format, ...) and
/// messages(id, topic_id, timestamp, data)), or a bag directory: its
/// metadata.yaml and the .db3 or .mcap files it lists (or, without one, the
/// directory's .db3 and .mcap files in name order), read one after the other
/// into one log. Files are told apart by their magic bytes.
#pragma once
#include <string>
#include <string_view>

#include "cubecal/io/message_log.hpp"

namespace cubecal::io {

/// "SQLite format 3\0", the first 16 bytes of an SQLite database.
inline constexpr std::string_view kSqliteMagic{"SQLite format 3\0", 16};

/// Whether `head` (the first bytes of a file) starts with kSqliteMagic. Throws nothing.
bool looks_like_sqlite(std::string_view head) noexcept;

/// Whether `path` is a regular file that starts with the SQLite magic.
bool is_sqlite_file(const std::string& path);

/// A rosbag2 SQLite database, opened read only and immutable (no journal is
/// attempted: the bag may sit on a read-only medium). Messages in the order
/// of their timestamp (then id), as ros2 bag play gives them. Throws
/// InputError naming `path` (not SQLite, no rosbag2 tables, a message of an
/// undeclared topic, a corrupt database).
MessageLog read_db3(const std::string& path);

/// A bag directory (see above). Throws InputError naming the directory or
/// the file at fault.
MessageLog read_ros2_bag_directory(const std::string& dir);

}  // namespace cubecal::io
