/// @file
/// MCAP files (mcap.dev/spec), read without a ROS install: the ROS 2 (and
/// ROS 1) profile's channels (topic, schema name = message type, message
/// encoding) and every message's log time and bytes, from the data section's
/// records and chunks (uncompressed, "zstd" or "lz4" frames). The summary
/// section is optional (a killed recording lacks it); its Statistics
/// record's per-channel message counts become LogTopic::counted.
#pragma once
#include <string>
#include <string_view>

#include "cubecal/io/message_log.hpp"

namespace cubecal::io {

/// "\x89MCAP0\r\n", the first (and last) eight bytes of an MCAP file.
inline constexpr std::string_view kMcapMagic{"\x89MCAP0\r\n", 8};

/// Whether `head` (the first bytes of a file) starts with kMcapMagic. Throws nothing.
bool looks_like_mcap(std::string_view head) noexcept;

/// Parses a whole MCAP file held in memory. Every length is checked against
/// the bytes there are, and chunk CRCs and the data section CRC when they
/// are not 0 ("not computed"): a truncated or corrupt file is an InputError
/// naming `file` and the byte offset ("FILE: byte 1234: ..."). A file that
/// ends between records (a killed recording) reads up to there.
MessageLog parse_mcap(std::string_view bytes, const std::string& file);

/// The same from a file (memory-mapped).
MessageLog read_mcap(const std::string& path);

}  // namespace cubecal::io
