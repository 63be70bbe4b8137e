#include "ros1_messages.hpp"

#include <cstring>

namespace cubecal::io::detail {

namespace {

class Cursor {
 public:
  explicit Cursor(std::string_view b) : b_(b) {}

  std::uint32_t u32(const char* what) {
    need(4, what);
    const auto* u = reinterpret_cast<const unsigned char*>(b_.data() + p_);
    p_ += 4;
    return static_cast<std::uint32_t>(u[0]) | static_cast<std::uint32_t>(u[1]) << 8 |
           static_cast<std::uint32_t>(u[2]) << 16 | static_cast<std::uint32_t>(u[3]) << 24;
  }
  double f64(const char* what) {
    need(8, what);
    std::uint64_t v = 0;
    for (int k = 7; k >= 0; --k) v = v << 8 | static_cast<unsigned char>(b_[p_ + static_cast<std::size_t>(k)]);
    p_ += 8;
    double d;
    std::memcpy(&d, &v, sizeof d);
    return d;
  }
  void skip_f64(std::size_t n, const char* what) {
    need(8 * n, what);
    p_ += 8 * n;
  }
  void skip_string(const char* what) {
    const std::size_t at = p_;
    const std::uint32_t len = u32(what);
    if (len > b_.size() - p_) {
      throw MessageLayoutError(at, std::string(what) + " of " + std::to_string(len) + " bytes runs past the message (" +
                                       std::to_string(b_.size() - p_) + " bytes left)");
    }
    p_ += len;
  }
  Stamp header() {
    u32("header.seq");
    Stamp s;
    s.sec = u32("header.stamp.sec");
    s.nsec = u32("header.stamp.nsec");
    skip_string("header.frame_id");
    return s;
  }
  void end(const char* type) const {
    if (p_ != b_.size())
      throw MessageLayoutError(p_, std::to_string(b_.size() - p_) + " bytes left over after a " + type +
                                       " (the message is of another definition)");
  }

 private:
  void need(std::size_t n, const char* what) const {
    if (n > b_.size() - p_)
      throw MessageLayoutError(p_, std::string("message ends (") + std::to_string(b_.size()) + " bytes) inside " + what);
  }
  std::string_view b_;
  std::size_t p_ = 0;
};

}  // namespace

ImuMessage decode_imu(std::string_view bytes) {
  Cursor c(bytes);
  ImuMessage m;
  m.stamp = c.header();
  c.skip_f64(4, "orientation");
  c.skip_f64(9, "orientation_covariance");
  for (double& v : m.angular_velocity) v = c.f64("angular_velocity");
  c.skip_f64(9, "angular_velocity_covariance");
  for (double& v : m.linear_acceleration) v = c.f64("linear_acceleration");
  c.skip_f64(9, "linear_acceleration_covariance");
  c.end("sensor_msgs/Imu");
  return m;
}

MagneticFieldMessage decode_magnetic_field(std::string_view bytes) {
  Cursor c(bytes);
  MagneticFieldMessage m;
  m.stamp = c.header();
  for (double& v : m.magnetic_field) v = c.f64("magnetic_field");
  c.skip_f64(9, "magnetic_field_covariance");
  c.end("sensor_msgs/MagneticField");
  return m;
}

TemperatureMessage decode_temperature(std::string_view bytes) {
  Cursor c(bytes);
  TemperatureMessage m;
  m.stamp = c.header();
  m.temperature = c.f64("temperature");
  c.skip_f64(1, "variance");
  c.end("sensor_msgs/Temperature");
  return m;
}

}  // namespace cubecal::io::detail
