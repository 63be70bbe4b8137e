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
      throw MessageLayoutError(p_,
                               std::string("message ends (") + std::to_string(b_.size()) + " bytes) inside " + what);
  }
  std::string_view b_;
  std::size_t p_ = 0;
};

}  // namespace

ImuMessage decode_imu(std::string_view bytes) {
  Cursor c(bytes);
  return read_imu(c, "sensor_msgs/Imu");
}

MagneticFieldMessage decode_magnetic_field(std::string_view bytes) {
  Cursor c(bytes);
  return read_magnetic_field(c, "sensor_msgs/MagneticField");
}

TemperatureMessage decode_temperature(std::string_view bytes) {
  Cursor c(bytes);
  return read_temperature(c, "sensor_msgs/Temperature");
}

}  // namespace cubecal::io::detail
