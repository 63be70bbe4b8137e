// A serial device (a USB-serial adapter, a UART, a pseudo-terminal) as a
// source: 8 data bits, no parity, one stop bit, no flow control, at the baud
// rate asked for. Through libserialport for the ports it knows (it finds a
// port by its entry in /sys/class/tty); a terminal it does not list, such as
// a pseudo-terminal (/dev/pts/N, what a simulated board or socat gives), is
// opened and set raw through termios directly. A device that disappears (a
// USB hiccup) is reported once (lost) and reopened with a growing wait until
// it is back (reconnected).
#include <fcntl.h>
#include <libserialport.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>
#include <utility>

#include "cubecal/acquire/source.hpp"
#include "cubecal/error.hpp"
#include "detail/reconnect_backoff.hpp"
#include "detail/wait_readable.hpp"

namespace cubecal::acquire {

namespace {

std::string last_error() {
  char* msg = sp_last_error_message();
  std::string s = msg != nullptr ? msg : "unknown error";
  sp_free_error_message(msg);
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s;
}

// The termios speed of a baud rate; B0 for one termios has no constant for.
speed_t termios_speed(int baud) {
  static constexpr std::pair<int, speed_t> kSpeeds[] = {
      {1200, B1200},       {2400, B2400},      {4800, B4800},       {9600, B9600},       {19200, B19200},
      {38400, B38400},     {57600, B57600},    {115200, B115200},   {230400, B230400},   {460800, B460800},
      {500000, B500000},   {921600, B921600},  {1000000, B1000000}, {1500000, B1500000}, {2000000, B2000000},
      {3000000, B3000000}, {4000000, B4000000}};
  for (const auto& [b, s] : kSpeeds)
    if (b == baud) return s;
  return B0;
}

// A terminal libserialport does not list, opened read-only, non-blocking and
// raw at `baud` 8N1; -1 with `why` saying what failed.
int open_terminal(const std::string& device, int baud, std::string& why) {
  const speed_t speed = termios_speed(baud);
  if (speed == B0) {
    why = std::to_string(baud) + " baud is not a standard rate of this terminal";
    return -1;
  }
  const int fd = ::open(device.c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    why = std::strerror(errno);
    return -1;
  }
  termios t{};
  if (!::isatty(fd) || ::tcgetattr(fd, &t) != 0) {
    why = "not a terminal";
    ::close(fd);
    return -1;
  }
  ::cfmakeraw(&t);
  t.c_cflag &= ~static_cast<tcflag_t>(PARENB | CSTOPB | CSIZE | CRTSCTS);
  t.c_cflag |= CS8 | CLOCAL | CREAD;
  t.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  if (::cfsetispeed(&t, speed) != 0 || ::cfsetospeed(&t, speed) != 0 || ::tcsetattr(fd, TCSANOW, &t) != 0) {
    why = "cannot set " + std::to_string(baud) + " baud 8N1: " + std::strerror(errno);
    ::close(fd);
    return -1;
  }
  return fd;
}

// An open port, or nullptr with `why` saying what failed (`listed`: false
// when libserialport does not know the device at all).
sp_port* open_port(const std::string& device, int baud, std::string& why, bool& listed) {
  sp_port* port = nullptr;
  listed = true;
  if (sp_get_port_by_name(device.c_str(), &port) != SP_OK) {
    why = last_error();
    listed = false;
    return nullptr;
  }
  if (sp_open(port, SP_MODE_READ) != SP_OK) {
    why = last_error();
    sp_free_port(port);
    return nullptr;
  }
  if (sp_set_baudrate(port, baud) != SP_OK || sp_set_bits(port, 8) != SP_OK ||
      sp_set_parity(port, SP_PARITY_NONE) != SP_OK || sp_set_stopbits(port, 1) != SP_OK ||
      sp_set_flowcontrol(port, SP_FLOWCONTROL_NONE) != SP_OK) {
    why = "cannot set " + std::to_string(baud) + " baud 8N1: " + last_error();
    sp_close(port);
    sp_free_port(port);
    return nullptr;
  }
  return port;
}

class SerialSource final : public Source {
 public:
  SerialSource(std::string device, const SourceOptions& opt)
      : device_(std::move(device)), baud_(opt.baud), backoff_(opt.reconnect_first_s, opt.reconnect_max_s) {
    if (baud_ <= 0) throw UsageError(Field::baud, "the baud rate must be positive (e.g. {baud} 115200)");
    std::string why;
    if (!open(why))
      throw UsageError(Field::source,
                       device_ + ": cannot open the serial device (" + why +
                           "); SOURCE is -, tcp:HOST:PORT, udp:PORT or a serial device such as /dev/ttyUSB0");
  }
  ~SerialSource() override { close(); }

  ReadResult read(char* buffer, std::size_t capacity, int timeout_ms) override {
    if (port_ == nullptr && fd_ < 0) {
      if (!backoff_.wait_for_attempt(timeout_ms)) return {ReadResult::Status::timeout, 0};
      std::string why;
      if (!open(why)) {
        backoff_.failed();
        return {ReadResult::Status::timeout, 0};
      }
      backoff_.succeeded();
      return {ReadResult::Status::reconnected, 0};
    }
    if (fd_ >= 0) return read_terminal(buffer, capacity, timeout_ms);
    const sp_return n =
        sp_blocking_read_next(port_, buffer, capacity, static_cast<unsigned>(timeout_ms > 0 ? timeout_ms : 1));
    if (n > 0) return {ReadResult::Status::data, static_cast<std::size_t>(n)};
    if (n == 0) return {ReadResult::Status::timeout, 0};
    close();  // the device went away (unplugged, hung up)
    backoff_.lost();
    return {ReadResult::Status::lost, 0};
  }

  std::string describe() const override { return device_ + " at " + std::to_string(baud_) + " baud"; }

 private:
  // libserialport for a port it lists, termios for a terminal it does not.
  bool open(std::string& why) {
    bool listed = true;
    port_ = open_port(device_, baud_, why, listed);
    if (port_ != nullptr) return true;
    if (listed) return false;
    std::string why_terminal;
    fd_ = open_terminal(device_, baud_, why_terminal);
    if (fd_ >= 0) return true;
    why = why_terminal;
    return false;
  }

  ReadResult read_terminal(char* buffer, std::size_t capacity, int timeout_ms) {
    if (!detail::wait_readable(fd_, timeout_ms > 0 ? timeout_ms : 1, describe()))
      return {ReadResult::Status::timeout, 0};
    const ssize_t n = ::read(fd_, buffer, capacity);
    if (n > 0) return {ReadResult::Status::data, static_cast<std::size_t>(n)};
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) return {ReadResult::Status::timeout, 0};
    close();  // hung up (the other side of a pseudo-terminal closed) or gone
    backoff_.lost();
    return {ReadResult::Status::lost, 0};
  }

  void close() {
    if (port_ != nullptr) {
      sp_close(port_);
      sp_free_port(port_);
      port_ = nullptr;
    }
    if (fd_ >= 0) {
      ::close(fd_);
      fd_ = -1;
    }
  }

  std::string device_;
  int baud_;
  detail::ReconnectBackoff backoff_;
  sp_port* port_ = nullptr;
  int fd_ = -1;  // a terminal opened through termios
};

}  // namespace

std::unique_ptr<Source> open_serial_source(const std::string& device, const SourceOptions& opt) {
  return std::make_unique<SerialSource>(device, opt);
}

}  // namespace cubecal::acquire
