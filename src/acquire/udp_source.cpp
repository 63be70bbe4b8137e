// UDP datagrams to a local port as a source: the payloads in order of
// arrival; a datagram may hold one line or several, and its end is the end
// of a line (record_ends). Bound to the loopback address 127.0.0.1 unless an
// address is given (udp:0.0.0.0:PORT, udp:[::]:PORT for every interface).
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>
#include <vector>

#include "cubecal/acquire/source.hpp"
#include "detail/wait_readable.hpp"
#include "cubecal/error.hpp"

namespace cubecal::acquire {

namespace {

class UdpSource final : public Source {
 public:
  UdpSource(std::string address, std::string port) : address_(std::move(address)), port_(std::move(port)) {
    addrinfo hints{};
    hints.ai_family = address_.empty() ? AF_INET : AF_UNSPEC;
    hints.ai_socktype = SOCK_DGRAM;
    hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
    addrinfo* res = nullptr;
    const int rc = ::getaddrinfo(address_.empty() ? "127.0.0.1" : address_.c_str(), port_.c_str(), &hints, &res);
    if (rc != 0)
      throw UsageError(Field::source, describe() + ": not a local address (" + ::gai_strerror(rc) +
                                          "); udp:PORT listens on 127.0.0.1, udp:0.0.0.0:PORT on every interface");
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
    ends_.clear();
    while (got < capacity) {
      const ssize_t n = ::recv(fd_, buffer + got, capacity - got, got == 0 ? 0 : MSG_DONTWAIT);
      if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) break;
        throw std::system_error(errno, std::generic_category(), describe() + ": recv failed");
      }
      got += static_cast<std::size_t>(n);
      ends_.push_back(got);
      if (capacity - got < 65536) break;  // the next datagram might not fit
    }
    return got > 0 ? ReadResult{ReadResult::Status::data, got} : ReadResult{ReadResult::Status::timeout, 0};
  }

  std::string describe() const override {
    if (address_.empty()) return "udp:" + port_;
    return "udp:" + (address_.find(':') != std::string::npos ? "[" + address_ + "]" : address_) + ":" + port_;
  }

  std::span<const std::size_t> record_ends() const override { return ends_; }

 private:
  std::string address_, port_;
  std::vector<std::size_t> ends_;
  int fd_ = -1;
};

}  // namespace

std::unique_ptr<Source> open_udp_source(const std::string& address, const std::string& port) {
  return std::make_unique<UdpSource>(address, port);
}

}  // namespace cubecal::acquire
