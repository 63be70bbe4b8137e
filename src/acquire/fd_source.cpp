// A pipe, the standard input or any readable file descriptor as a source.
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

#include "cubecal/acquire/source.hpp"
#include "detail/wait_readable.hpp"

namespace cubecal::acquire {

namespace {

class FdSource final : public Source {
 public:
  FdSource(int fd, std::string label) : fd_(fd), label_(std::move(label)) {}

  ReadResult read(char* buffer, std::size_t capacity, int timeout_ms) override {
    if (ended_) return {ReadResult::Status::end, 0};
    if (!detail::wait_readable(fd_, timeout_ms, label_)) return {ReadResult::Status::timeout, 0};
    const ssize_t n = ::read(fd_, buffer, capacity);
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) return {ReadResult::Status::timeout, 0};
      throw std::system_error(errno, std::generic_category(), label_ + ": read failed");
    }
    if (n == 0) {
      ended_ = true;
      return {ReadResult::Status::end, 0};
    }
    return {ReadResult::Status::data, static_cast<std::size_t>(n)};
  }

  std::string describe() const override { return label_; }

 private:
  int fd_;
  std::string label_;
  bool ended_ = false;
};

}  // namespace

std::unique_ptr<Source> open_fd_source(int fd, std::string label) {
  return std::make_unique<FdSource>(fd, std::move(label));
}

}  // namespace cubecal::acquire
