// A Series from a ROS bag (ROS 1 .bag, MCAP or rosbag2 SQLite, read into a
// MessageLog): the sensor messages of the chosen topics as channels with
// fixed names and SI units. Used by read_series.
#pragma once
#include "cubecal/io/message_log.hpp"
#include "cubecal/io/series.hpp"

namespace cubecal::io::detail {

// Channels (per message type, in ROS 1 or ROS 2 spelling: sensor_msgs/Imu
// or sensor_msgs/msg/Imu; serialized as ROS 1 or CDR):
//   sensor_msgs/Imu            gx gy gz (rad/s), ax ay az (m/s^2)
//   sensor_msgs/MagneticField  mx my mz (T)
//   sensor_msgs/Temperature    temp (degC; left out of the default channels like a text temperature column)
// Topics: opt.topics, or the log's only sensor_msgs/Imu topic. Several
// topics must hold as many messages, stamped alike. Time: header.stamp, or
// the log time (when the log recorded each message) with opt.time_col
// "record". Throws InputError (missing topic, corrupt message, non-finite
// value, gaps...) and UsageError (an option that does not apply to a bag).
Series read_bag_series(const MessageLog& bag, bool gzip, const SeriesOptions& opt);

}  // namespace cubecal::io::detail
