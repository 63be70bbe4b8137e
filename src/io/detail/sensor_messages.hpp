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

struct ImuMessage {  // sensor_msgs/Imu
  Stamp stamp;
  double angular_velocity[3] = {};     // rad/s
  double linear_acceleration[3] = {};  // m/s^2
};
struct MagneticFieldMessage {  // sensor_msgs/MagneticField
  Stamp stamp;
  double magnetic_field[3] = {};  // T
};
struct TemperatureMessage {  // sensor_msgs/Temperature
  Stamp stamp;
  double temperature = 0.0;  // degC
};

// The fields of each message in their order, read through a cursor of
// either serialization (header(), f64(what), skip_f64(n, what), end(type)
// checking that the bytes are used up).
template <class Cursor>
ImuMessage read_imu(Cursor& c, const char* type) {
  ImuMessage m;
  m.stamp = c.header();
  c.skip_f64(4, "orientation");
  c.skip_f64(9, "orientation_covariance");
  for (double& v : m.angular_velocity) v = c.f64("angular_velocity");
  c.skip_f64(9, "angular_velocity_covariance");
  for (double& v : m.linear_acceleration) v = c.f64("linear_acceleration");
  c.skip_f64(9, "linear_acceleration_covariance");
  c.end(type);
  return m;
}

template <class Cursor>
MagneticFieldMessage read_magnetic_field(Cursor& c, const char* type) {
  MagneticFieldMessage m;
  m.stamp = c.header();
  for (double& v : m.magnetic_field) v = c.f64("magnetic_field");
  c.skip_f64(9, "magnetic_field_covariance");
  c.end(type);
  return m;
}

template <class Cursor>
TemperatureMessage read_temperature(Cursor& c, const char* type) {
  TemperatureMessage m;
  m.stamp = c.header();
  m.temperature = c.f64("temperature");
  c.skip_f64(1, "variance");
  c.end(type);
  return m;
}

}  // namespace cubecal::io::detail
