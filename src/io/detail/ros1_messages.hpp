// ROS 1 serialization of the sensor messages cubecal reads: little-endian,
// no padding; a string is uint32 length + bytes. Every message must use its
// bytes exactly: a length that runs past the end, or bytes left over, is a
// MessageLayoutError giving the position inside the message.
#pragma once
#include <string_view>

#include "sensor_messages.hpp"

namespace cubecal::io::detail {

ImuMessage decode_imu(std::string_view bytes);
MagneticFieldMessage decode_magnetic_field(std::string_view bytes);
TemperatureMessage decode_temperature(std::string_view bytes);

}  // namespace cubecal::io::detail
