// ROS 2 serialization (CDR, XCDR version 1, as rmw_fastrtps and
// rmw_cyclonedds write it) of the sensor messages cubecal reads: a 4-byte
// encapsulation header (00 01 little endian, 00 00 big endian; its last
// byte's two low bits count padding bytes at the end), then the fields,
// each aligned to its size relative to the byte after the header; a string
// is uint32 length (counting its NUL) + bytes + NUL. Every length is checked
// against the bytes there are, and a message must use its bytes exactly
// (but for the padding the header declares): otherwise MessageLayoutError
// with the position inside the message.
#pragma once
#include <string_view>

#include "sensor_messages.hpp"

namespace cubecal::io::detail {

ImuMessage decode_cdr_imu(std::string_view bytes);
MagneticFieldMessage decode_cdr_magnetic_field(std::string_view bytes);
TemperatureMessage decode_cdr_temperature(std::string_view bytes);

}  // namespace cubecal::io::detail
