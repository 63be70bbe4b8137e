// Where a recording's bytes come from: the standard input (or any pipe), a
// TCP server the recorder connects to, UDP datagrams to a local port, or a
// serial device. Every source is read the same way, a batch of bytes at a
// time with a timeout, so that the recorder's loop can keep its flush and
// fsync deadlines whatever the source does.
#pragma once
#include <cstddef>
#include <memory>
#include <span>
#include <string>

namespace cubecal::acquire {

struct ReadResult {
  enum class Status {
    data,         // `bytes` bytes were read
    timeout,      // nothing within the timeout (or the source is waiting to reconnect)
    end,          // the source ended for good (end of file, pipe closed)
    lost,         // the connection dropped; the source tries to reconnect on later reads
    reconnected,  // the connection is back (after `lost`)
  };
  Status status = Status::timeout;
  std::size_t bytes = 0;
};

class Source {
 public:
  virtual ~Source() = default;
  // Reads at most `capacity` bytes into `buffer`, waiting at most
  // `timeout_ms` milliseconds (0: do not wait). A signal interrupting the wait
  // returns timeout. Throws std::system_error for a failure that cannot be
  // recovered from.
  virtual ReadResult read(char* buffer, std::size_t capacity, int timeout_ms) = 0;
  // "stdin", "tcp:127.0.0.1:5000", "udp:5000", "/dev/ttyUSB0 at 115200 baud".
  virtual std::string describe() const = 0;
  // The offsets in the last read's bytes where a record of the source ends
  // (each UDP datagram ends one: the end of a line, or of a frame); empty for
  // a byte stream.
  virtual std::span<const std::size_t> record_ends() const { return {}; }
};

struct SourceOptions {
  int baud = 115200;                // serial devices
  double reconnect_first_s = 0.25;  // first wait before reconnecting; doubles each failure
  double reconnect_max_s = 8.0;     // longest wait between attempts
};

// SOURCE as the command line gives it: "-" (the standard input),
// "tcp:HOST:PORT", "udp:PORT" (the loopback address 127.0.0.1),
// "udp:ADDRESS:PORT" (a local address; 0.0.0.0 or [::] for every interface)
// or a serial device path. A port is a number from 1 to 65535. Opened (connected,
// bound) here, so that an unusable source is a UsageError before anything
// is recorded.
std::unique_ptr<Source> open_source(const std::string& spec, const SourceOptions& opt = {});

// The sources themselves.
std::unique_ptr<Source> open_fd_source(int fd, std::string label);  // a pipe or file descriptor; not closed
std::unique_ptr<Source> open_tcp_source(const std::string& host, const std::string& port, const SourceOptions& opt);
std::unique_ptr<Source> open_udp_source(const std::string& address, const std::string& port);
std::unique_ptr<Source> open_serial_source(const std::string& device, const SourceOptions& opt);

}  // namespace cubecal::acquire
