// A Series from a PX4 ULog file: the sensor topics chosen as channels with
// the names and SI units of the ROS path. Used by read_series.
#pragma once
#include <string_view>

#include "cubecal/io/series.hpp"
#include "cubecal/io/ulog.hpp"

namespace cubecal::io::detail {

// Topics (opt.topics, default sensor_combined; instance N > 0 of a topic is
// "name:N") and their channels, fields found by name in the log's formats:
//   sensor_combined       gyro_rad[3] -> gx gy gz (rad/s), accelerometer_m_s2[3] -> ax ay az (m/s^2)
//   vehicle_magnetometer  magnetometer_ga[3] -> mx my mz (gauss, converted to T like ROS MagneticField)
//   sensor_gyro           x y z -> gx gy gz (rad/s), temperature -> temp (degC)
//   sensor_accel          x y z -> ax ay az (m/s^2), temperature -> temp
//   sensor_mag            x y z -> mx my mz (gauss -> T), temperature -> temp
// (temp, like a text temperature column, is left out of the default
// channels; a temperature field that is NaN throughout gives no channel.)
// Time: the topic's `timestamp` field (microseconds), or the integer field
// opt.time_col names (e.g. timestamp_sample). Several topics must hold as
// many messages at the same instants: topics of different rates are refused
// with their rates. `bytes` are the file's (the messages' offsets point
// into them). Throws InputError "FILE: byte N: ..." and UsageError (an
// option that does not apply to a log).
Series read_ulog_series(const ULog& log, std::string_view bytes, bool gzip, const SeriesOptions& opt);

}  // namespace cubecal::io::detail
