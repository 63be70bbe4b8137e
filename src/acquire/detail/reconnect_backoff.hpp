// The waits between attempts to reopen a lost source: the first after
// `first_s`, each failure doubling it up to `max_s`; a success resets it.
#pragma once
#include <poll.h>

#include <algorithm>
#include <cmath>
#include <ctime>

namespace cubecal::acquire::detail {

inline double monotonic_s() {
  timespec t{};
  ::clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

class ReconnectBackoff {
 public:
  ReconnectBackoff(double first_s, double max_s) : first_(first_s), max_(max_s), wait_(first_s) {}

  // The connection was lost now: the first attempt after one wait.
  void lost() {
    wait_ = first_;
    next_ = monotonic_s() + wait_;
  }
  // An attempt failed: wait twice as long.
  void failed() {
    wait_ = std::min(max_, 2.0 * wait_);
    next_ = monotonic_s() + wait_;
  }
  void succeeded() { wait_ = first_; }

  // Sleeps until the next attempt is due or `timeout_ms` passed; true when due.
  bool wait_for_attempt(int timeout_ms) const {
    const double left = next_ - monotonic_s();
    if (left <= 0) return true;
    const int ms = static_cast<int>(std::ceil(left * 1000.0));
    ::poll(nullptr, 0, std::min(ms, timeout_ms));
    return ms <= timeout_ms;
  }

 private:
  double first_, max_, wait_;
  double next_ = 0.0;
};

}  // namespace cubecal::acquire::detail
