// ROS 1 serialization of the sensor messages cubecal reads: little-endian,
// no padding; a string is uint32 length + bytes. Every message must use its
// bytes exactly: a length that runs past the end, or bytes left over, is a
// MessageLayoutError giving the position inside the message.
#pragma once
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace cubecal::io::detail {

class MessageLayoutError : public std::runtime_error {
 public:
  MessageLayoutError(std::size_t position, const std::string& what) : std::runtime_error(what), position_(position) {}
  std::size_t position() const noexcept { return position_; }

 private:
  std::size_t position_;
};

struct Stamp {
  std::uint32_t sec = 0;
  std::uint32_t nsec = 0;
};

// std_msgs/Header + the fields cubecal uses.
struct ImuMessage {            // sensor_msgs/Imu
  Stamp stamp;
  double angular_velocity[3] = {};     // rad/s
  double linear_acceleration[3] = {};  // m/s^2
};
struct MagneticFieldMessage {  // sensor_msgs/MagneticField
  Stamp stamp;
  double magnetic_field[3] = {};       // T
};
struct TemperatureMessage {    // sensor_msgs/Temperature
  Stamp stamp;
  double temperature = 0.0;            // degC
};

ImuMessage decode_imu(std::string_view bytes);
MagneticFieldMessage decode_magnetic_field(std::string_view bytes);
TemperatureMessage decode_temperature(std::string_view bytes);

}  // namespace cubecal::io::detail
