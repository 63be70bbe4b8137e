// A Series from a ROS bag (ROS 1 .bag, MCAP or rosbag2 SQLite, read into a
// MessageLog): the sensor messages of the chosen topics as channels with
// fixed names and SI units. Used by read_series.
#pragma once
#include "cubecal/error.hpp"
#include "cubecal/io/message_log.hpp"
#include "cubecal/io/series.hpp"
#include "topic_channels.hpp"

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

// The parts of read_bag_series a streamed read (message_stream.cpp) shares.
// The options a bag cannot take refused (UsageError); true when its time is
// the log time (opt.time_col "record"), false for header.stamp.
bool bag_time_is_record(const std::string& file, const SeriesOptions& opt);
// The topics read (opt.topics, or the only sensor_msgs/Imu topic) among
// bag.topics; InputError listing them otherwise.
std::vector<const LogTopic*> choose_bag_topics(const MessageLog& bag, const SeriesOptions& opt, bool& by_default);
// Whether the topic is of sensor_msgs/Imu (in either spelling).
bool is_imu_topic(const LogTopic& topic);
// The channels of a topic's messages (names, units, fields; no values).
std::vector<TopicColumn> bag_columns(const LogTopic& topic);
// Appends the values of message m (of bag.topics[m.topic], whose channels
// `columns` are) and returns its time in seconds; InputError naming it as
// message `number` (1-based) of its topic when its bytes do not decode.
double decode_bag_message(const MessageLog& bag, const LogMessage& m, std::size_t number,
                          std::vector<TopicColumn>& columns, bool record_time);
// "message 12 of /imu (at byte 4096): what".
InputError bag_message_error(const MessageLog& bag, const LogMessage& m, std::size_t number, const std::string& topic,
                             const std::string& what, std::string hint);

}  // namespace cubecal::io::detail
