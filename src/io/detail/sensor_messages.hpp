// The sensor messages cubecal reads, as decoded from either serialization
// (ROS 1: ros1_messages.hpp; ROS 2 CDR: cdr_messages.hpp): the header stamp
// and the fields cubecal uses. A decoder that finds the bytes do not hold
// the message throws MessageLayoutError with the position inside them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace cubecal::io::detail {

class MessageLayoutError : public std::runtime_error {
 public:
  MessageLayoutError(std::size_t position, const std::string& what) : std::runtime_error(what), position_(position) {}
  std::size_t position() const noexcept { return position_; }

 private:
  std::size_t position_;
};

// std_msgs/Header's stamp: ROS 1 time (uint32 sec, uint32 nsec) or ROS 2
// builtin_interfaces/Time (int32 sec, uint32 nanosec).
struct Stamp {
  std::int64_t sec = 0;
  std::uint32_t nsec = 0;
};

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

}  // namespace cubecal::io::detail
