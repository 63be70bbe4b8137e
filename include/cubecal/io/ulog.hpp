/// @file
/// PX4 ULog files (versions 0 and 1), read without PX4 or pyulog: the format
/// definitions ('F'), the logged topics ('A' subscriptions, one per topic
/// and instance) and where each data message ('D') lies, with the dropouts
/// the logger reported ('O'). Fields are found by name in the format
/// definitions, not at fixed offsets: message layouts change between PX4
/// versions. Information, parameter, logging, sync and remove messages are
/// checked and counted; message types unknown to the format are skipped by
/// their size.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal::io {

/// "ULog" 0x01 0x12 0x35, the first bytes of every ULog file (then the
/// version byte and the start time).
inline constexpr std::string_view kULogMagic("ULog\x01\x12\x35", 7);

/// Whether `head` (the first bytes of a file) starts with kULogMagic.
bool looks_like_ulog(std::string_view head) noexcept;

/// One field of a format: `type name` or `type[count] name`; type is a
/// basic type (int8_t ... uint64_t, float, double, bool, char) or the name of
/// another format (a nested type).
struct ULogField {
  std::string type;              ///< without the array suffix: "float"
  std::string name;              ///< "gyro_rad"
  std::size_t count = 1;         ///< elements (1 for a scalar)
  bool array = false;            ///< declared as type[count]
  std::size_t offset = 0;        ///< bytes from the start of the message data (after msg_id)
  std::size_t element_size = 0;  ///< bytes of one element
};

/// A message format of a ULog: its fields, packed.
struct ULogFormat {
  /// The format's name: "sensor_gyro".
  std::string name;
  std::vector<ULogField> fields;  ///< in their order, packed
  std::size_t size = 0;           ///< bytes of a whole message
  /// Bytes a data message must hold at least: the logger leaves out the
  /// padding fields at the end ("_padding0").
  std::size_t logged_size = 0;
  /// The field named `name`, or null. Throws nothing.
  const ULogField* field(std::string_view name) const noexcept;
};

/// Where one data message of a ULog sits in the file.
struct ULogMessage {
  std::size_t offset = 0;  ///< byte offset of the message (its header) in the file
  std::size_t begin = 0;   ///< its data (after msg_id): bytes [begin, begin + size) of the file
  /// Bytes of the message data.
  std::size_t size = 0;
};

/// A logged topic: a format name and an instance (multi_id), with its data
/// messages. A topic removed ('R') and added again keeps one entry.
struct ULogTopic {
  std::string name;           ///< the format name: "sensor_gyro"
  std::uint8_t multi_id = 0;  ///< instance
  std::size_t format = 0;     ///< index in ULog::formats
  /// The topic's data messages, in file order.
  std::vector<ULogMessage> messages;
  /// "sensor_gyro" for instance 0, "sensor_gyro:1" for instance 1...
  std::string label() const;
};

/// A dropout the logger recorded: data lost for a while.
struct ULogDropout {
  std::size_t offset = 0;         ///< byte offset of the 'O' message
  std::uint16_t duration_ms = 0;  ///< data lost
};

/// A PX4 ULog file read whole: formats, topics, their messages and what else it logged.
struct ULog {
  /// The path given.
  std::string file;
  /// The file format's version byte.
  int version = 0;
  std::uint64_t start_us = 0;  ///< the logger's start time (microseconds)
  /// The message formats, in the order defined.
  std::vector<ULogFormat> formats;
  std::vector<ULogTopic> topics;  ///< in the order first added
  /// The dropouts, in file order.
  std::vector<ULogDropout> dropouts;
  std::size_t info_messages = 0;       ///< 'I' and 'M'
  std::size_t parameter_messages = 0;  ///< 'P' and 'Q'
  std::size_t logging_messages = 0;    ///< 'L' and 'C'
  std::size_t sync_messages = 0;       ///< 'S'
  std::size_t skipped_messages = 0;    ///< of types the format does not know
  bool appended_data = false;          ///< the 'B' message's DATA_APPENDED flag
  /// The format named `name`, or null. Throws nothing.
  const ULogFormat* format(std::string_view name) const noexcept;
  /// The format of topic `t`. Throws std::out_of_range for a topic of another log.
  const ULogFormat& format_of(const ULogTopic& t) const { return formats.at(t.format); }
  /// The sum of the dropouts' durations (ms). Throws nothing.
  std::size_t dropped_ms() const noexcept;
};

/// Parses a whole ULog file held in memory (`bytes` must outlive the
/// messages' offsets only, not the result). Every size is checked against
/// the bytes there are and every data message against its format: a
/// truncated or corrupt file, an incompatible flag, an unknown or circular
/// nested type, data for a topic never added is an InputError
/// "FILE: byte N: ...".
ULog parse_ulog(std::string_view bytes, const std::string& file);

}  // namespace cubecal::io
