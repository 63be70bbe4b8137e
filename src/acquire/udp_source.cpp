// UDP datagrams to a local port as a source: the payloads in order of
// arrival, read as one stream (a datagram may hold one line or several).
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "cubecal/acquire/source.hpp"
#include "detail/wait_readable.hpp"
#include "cubecal/error.hpp"

namespace cubecal::acquire {

namespace {

class UdpSource final : public Source {
 public:
  explicit UdpSource(std::string port) : port_(std::move(port)) {
    addrinfo hints{};
    hints.ai_family = AF_INET6;
    hints.ai_socktype = SOCK_DGRAM;
    hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
    addrinfo* res = nullptr;
    int rc = ::getaddrinfo(nullptr, port_.c_str(), &hints, &res);
    if (rc != 0) {
      hints.ai_family = AF_INET;
      rc = ::getaddrinfo(nullptr, port_.c_str(), &hints, &res);
    }
    if (rc != 0) throw UsageError(Field::source, describe() + ": not a port number (udp:PORT, e.g. udp:5000)");
    std::string why;
    for (addrinfo* a = res; a != nullptr && fd_ < 0; a = a->ai_next) {
      fd_ = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
      if (fd_ < 0) continue;
      if (a->ai_family == AF_INET6) {
        const int off = 0;  // IPv4 senders too
        ::setsockopt(fd_, IPPROTO_IPV6, IPV6_V6ONLY, &off, sizeof off);
      }
      const int big = 4 << 20;  // room for bursts while the recorder fsyncs
      ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &big, sizeof big);
      if (::bind(fd_, a->ai_addr, a->ai_addrlen) != 0) {
        why = std::strerror(errno);
        ::close(fd_);
        fd_ = -1;
      }
    }
    ::freeaddrinfo(res);
    if (fd_ < 0) throw UsageError(Field::source, describe() + ": cannot listen (" + why + "); choose a free port");
  }
  ~UdpSource() override {
    if (fd_ >= 0) ::close(fd_);
  }

  ReadResult read(char* buffer, std::size_t capacity, int timeout_ms) override {
    if (!detail::wait_readable(fd_, timeout_ms, describe())) return {ReadResult::Status::timeout, 0};
    // Several datagrams per batch, as many as are waiting and fit.
    std::size_t got = 0;
    while (got < capacity) {
      const ssize_t n = ::recv(fd_, buffer + got, capacity - got, got == 0 ? 0 : MSG_DONTWAIT);
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) break;
        throw std::system_error(errno, std::generic_category(), describe() + ": recv failed");
      }
      got += static_cast<std::size_t>(n);
      if (capacity - got < 65536) break;  // the next datagram might not fit
    }
    return got > 0 ? ReadResult{ReadResult::Status::data, got} : ReadResult{ReadResult::Status::timeout, 0};
  }

  std::string describe() const override { return "udp:" + port_; }

 private:
  std::string port_;
  int fd_ = -1;
};

}  // namespace

std::unique_ptr<Source> open_udp_source(const std::string& port) { return std::make_unique<UdpSource>(port); }

}  // namespace cubecal::acquire
