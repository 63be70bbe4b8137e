// The messages of a robot log (ROS 1 bag, MCAP, rosbag2 .db3 or bag
// directory) a batch at a time, for a streamed read (message_stream.cpp):
// a ROS 1 or MCAP file one top-level record (a chunk) at a time, a .db3
// through an SQL cursor. Each batch is checked as read_series' readers
// check the whole log.
#pragma once
#include <cstddef>
#include <memory>
#include <string>

#include "cubecal/io/message_log.hpp"

namespace cubecal::io::detail {

class MessageSource {
 public:
  virtual ~MessageSource() = default;
  // The next messages into `batch` (file, parts, every topic declared so
  // far with the messages counted so far, indices kept from batch to
  // batch; messages and payload: only the new ones). False at the end of
  // the log, after the checks of its end. Throws InputError as the
  // whole-log readers do.
  virtual bool next(MessageLog& batch) = 0;
  // The bytes of the log and how many are read (progress).
  std::size_t total_bytes = 0, bytes_read = 0;
};

// A ROS 1 bag, an MCAP file, a rosbag2 .db3 (its messages in the order of
// their timestamps, as read_db3) and a rosbag2 directory (its files in
// turn). Throws InputError when the file cannot be opened or does not start
// as the format does.
std::unique_ptr<MessageSource> open_ros1_source(const std::string& path);
std::unique_ptr<MessageSource> open_mcap_source(const std::string& path);
std::unique_ptr<MessageSource> open_db3_source(const std::string& path);
std::unique_ptr<MessageSource> open_bag_directory_source(const std::string& dir);

}  // namespace cubecal::io::detail
