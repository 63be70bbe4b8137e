#include "paced_output.hpp"

#include <unistd.h>
#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cmath>
#include <ctime>
#include <system_error>

namespace cubecal::cli {

namespace {

std::int64_t now_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void sleep_until_ns(std::int64_t t) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(t % 1'000'000'000);
  while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

// Wake-ups at least this far apart: at a high rate the samples due within
// it go out in one write.
constexpr std::int64_t kMinWakeNs = 1'000'000;

}  // namespace

PacedOutput::PacedOutput(int fd, double rate_hz) : fd_(fd), rate_hz_(rate_hz) { std::signal(SIGPIPE, SIG_IGN); }

std::int64_t PacedOutput::due_ns(std::size_t k) const {
  // k / rate from t0 every time (no accumulated sum): exact to a few
  // nanoseconds for 1e9 samples.
  return t0_ns_ + std::llround(static_cast<double>(k) * 1e9 / rate_hz_);
}

bool PacedOutput::write_now(std::string_view bytes) {
  queue_.append(bytes);
  return flush();
}

bool PacedOutput::flush() {
  if (gone_) return false;
  const char* p = queue_.data();
  std::size_t left = queue_.size();
  while (left > 0) {
    const ssize_t n = ::write(fd_, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) {
        pollfd pfd{fd_, POLLOUT, 0};
        ::poll(&pfd, 1, -1);
        continue;
      }
      if (errno == EPIPE) {
        gone_ = true;
        queue_.clear();
        queued_ = 0;
        return false;
      }
      throw std::system_error(errno, std::generic_category(), "could not write the standard output");
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  if (queued_ > 0) {
    const std::int64_t t = now_ns();
    worst_late_ns_ = std::max(worst_late_ns_, t - due_ns(first_queued_));
    last_write_ns_ = t;
  }
  written_ += queued_;
  queued_ = 0;
  queue_.clear();
  return true;
}

bool PacedOutput::sample(std::size_t k, std::string_view bytes) {
  if (gone_) return false;
  if (!started_) {
    // The clock starts with the first sample, once it exists (a model's
    // first block can take a while).
    t0_ns_ = now_ns() - (due_ns(k) - t0_ns_);
    last_write_ns_ = t0_ns_;
    started_ = true;
  }
  const std::int64_t due = due_ns(k);
  if (due > now_ns()) {
    if (!flush()) return false;
    sleep_until_ns(std::max(due, last_write_ns_ + kMinWakeNs));
  }
  if (queued_ == 0) first_queued_ = k;
  queue_.append(bytes);
  ++queued_;
  return true;
}

bool PacedOutput::finish() { return flush(); }

}  // namespace cubecal::cli
