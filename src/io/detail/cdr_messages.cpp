#include "cdr_messages.hpp"

#include <cstdint>
#include <cstring>
#include <string>

namespace cubecal::io::detail {

namespace {

class CdrCursor {
 public:
  explicit CdrCursor(std::string_view b) : b_(b) {
    if (b_.size() < 4)
      throw MessageLayoutError(
          0, "message of " + std::to_string(b_.size()) + " bytes ends inside its 4-byte CDR encapsulation header");
    const auto kind = static_cast<unsigned char>(b_[1]);
    if (b_[0] != 0 || (kind != 0 && kind != 1))
      throw MessageLayoutError(0, "CDR encapsulation " + hex(b_[0]) + " " + hex(b_[1]) +
                                      " is not plain CDR (00 00 big endian, 00 01 little endian)");
    little_ = kind == 1;
    padding_ = static_cast<unsigned char>(b_[3]) & 3u;
    p_ = 4;
  }

  std::uint32_t u32(const char* what) {
    align(4, what);
    need(4, what);
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v = v << 8 | static_cast<std::uint32_t>(byte(little_ ? 3 - k : k));
    p_ += 4;
    return v;
  }
  double f64(const char* what) {
    align(8, what);
    need(8, what);
    std::uint64_t v = 0;
    for (int k = 0; k < 8; ++k) v = v << 8 | byte(little_ ? 7 - k : k);
    p_ += 8;
    double d;
    std::memcpy(&d, &v, sizeof d);
    return d;
  }
  void skip_f64(std::size_t n, const char* what) {
    align(8, what);
    need(8 * n, what);
    p_ += 8 * n;
  }
  void skip_string(const char* what) {
    const std::size_t at = p_;
    const std::uint32_t len = u32(what);
    if (len > b_.size() - p_)
      throw MessageLayoutError(at, std::string(what) + " of " + std::to_string(len) + " bytes runs past the message (" +
                                       std::to_string(b_.size() - p_) + " bytes left)");
    if (len > 0 && b_[p_ + len - 1] != '\0')
      throw MessageLayoutError(at, std::string(what) + " of " + std::to_string(len) + " bytes does not end in a NUL");
    p_ += len;
  }
  // std_msgs/Header: builtin_interfaces/Time stamp (int32 sec, uint32
  // nanosec), string frame_id.
  Stamp header() {
    Stamp s;
    s.sec = static_cast<std::int32_t>(u32("header.stamp.sec"));
    s.nsec = u32("header.stamp.nanosec");
    skip_string("header.frame_id");
    return s;
  }
  void end(const char* type) const {
    const std::size_t left = b_.size() - p_;
    if (left != 0 && left != padding_)
      throw MessageLayoutError(
          p_, std::to_string(left) + " bytes left over after a " + type + " (the message is of another definition)");
  }

 private:
  static std::string hex(char c) {
    static constexpr char kDigits[] = "0123456789abcdef";
    const auto u = static_cast<unsigned char>(c);
    return {kDigits[u >> 4], kDigits[u & 15]};
  }
  std::uint64_t byte(int k) const { return static_cast<unsigned char>(b_[p_ + static_cast<std::size_t>(k)]); }
  // Alignment is relative to the byte after the encapsulation header.
  void align(std::size_t n, const char* what) {
    const std::size_t pad = (n - (p_ - 4) % n) % n;
    need(pad, what);
    p_ += pad;
  }
  void need(std::size_t n, const char* what) const {
    if (n > b_.size() - p_)
      throw MessageLayoutError(p_,
                               std::string("message ends (") + std::to_string(b_.size()) + " bytes) inside " + what);
  }
  std::string_view b_;
  std::size_t p_ = 0;
  bool little_ = true;
  std::size_t padding_ = 0;
};

}  // namespace

ImuMessage decode_cdr_imu(std::string_view bytes) {
  CdrCursor c(bytes);
  return read_imu(c, "sensor_msgs/msg/Imu");
}

MagneticFieldMessage decode_cdr_magnetic_field(std::string_view bytes) {
  CdrCursor c(bytes);
  return read_magnetic_field(c, "sensor_msgs/msg/MagneticField");
}

TemperatureMessage decode_cdr_temperature(std::string_view bytes) {
  CdrCursor c(bytes);
  return read_temperature(c, "sensor_msgs/msg/Temperature");
}

}  // namespace cubecal::io::detail
