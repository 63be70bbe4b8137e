// A TCP server as a source: the recorder is the client. A dropped
// connection is reported once (lost), then retried with a growing wait
// until it is back (reconnected), which the recorder notes as an event.
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "cubecal/acquire/source.hpp"
#include "detail/wait_readable.hpp"
#include "cubecal/error.hpp"
#include "detail/reconnect_backoff.hpp"

namespace cubecal::acquire {

namespace {

// A connected socket, or -1 with `why` saying what failed.
int connect_to(const std::string& host, const std::string& port, std::string& why) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* res = nullptr;
  const int rc = ::getaddrinfo(host.c_str(), port.c_str(), &hints, &res);
  if (rc != 0) {
    why = ::gai_strerror(rc);
    return -1;
  }
  int fd = -1;
  for (addrinfo* a = res; a != nullptr; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      why = std::strerror(errno);
      continue;
    }
    // connect() gives up after SO_SNDTIMEO on Linux: a host that does not
    // answer must not stall the recorder's deadlines for minutes.
    timeval tv{2, 0};
    ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    if (::connect(fd, a->ai_addr, a->ai_addrlen) == 0) break;
    why = std::strerror(errno);
    ::close(fd);
    fd = -1;
  }
  ::freeaddrinfo(res);
  if (fd >= 0) {
    const int on = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_KEEPALIVE, &on, sizeof on);
  }
  return fd;
}

class TcpSource final : public Source {
 public:
  TcpSource(std::string host, std::string port, const SourceOptions& opt)
      : host_(std::move(host)), port_(std::move(port)), backoff_(opt.reconnect_first_s, opt.reconnect_max_s) {
    std::string why;
    fd_ = connect_to(host_, port_, why);
    if (fd_ < 0)
      throw UsageError(Field::source, describe() + ": cannot connect (" + why +
                                          "); start the sender first, or check the host and port");
  }
  ~TcpSource() override {
    if (fd_ >= 0) ::close(fd_);
  }

  ReadResult read(char* buffer, std::size_t capacity, int timeout_ms) override {
    if (fd_ < 0) {
      if (!backoff_.wait_for_attempt(timeout_ms)) return {ReadResult::Status::timeout, 0};
      std::string why;
      fd_ = connect_to(host_, port_, why);
      if (fd_ < 0) {
        backoff_.failed();
        return {ReadResult::Status::timeout, 0};
      }
      backoff_.succeeded();
      return {ReadResult::Status::reconnected, 0};
    }
    if (!detail::wait_readable(fd_, timeout_ms, describe())) return {ReadResult::Status::timeout, 0};
    const ssize_t n = ::recv(fd_, buffer, capacity, 0);
    if (n > 0) return {ReadResult::Status::data, static_cast<std::size_t>(n)};
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) return {ReadResult::Status::timeout, 0};
    ::close(fd_);  // closed by the peer (n == 0) or reset
    fd_ = -1;
    backoff_.lost();
    return {ReadResult::Status::lost, 0};
  }

  std::string describe() const override {
    return "tcp:" + (host_.find(':') != std::string::npos ? "[" + host_ + "]" : host_) + ":" + port_;
  }

 private:
  std::string host_, port_;
  detail::ReconnectBackoff backoff_;
  int fd_ = -1;
};

}  // namespace

std::unique_ptr<Source> open_tcp_source(const std::string& host, const std::string& port, const SourceOptions& opt) {
  return std::make_unique<TcpSource>(host, port, opt);
}

}  // namespace cubecal::acquire
