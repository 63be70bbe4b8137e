// The wait every source's read starts with: poll one descriptor for input.
#pragma once
#include <poll.h>

#include <cerrno>
#include <string>
#include <system_error>

namespace cubecal::acquire::detail {

// True when `fd` has input (or a hang-up to read) within `timeout_ms`;
// false on a timeout or a signal (the recorder's loop then checks its flags
// and deadlines). Throws std::system_error naming `label` when poll fails.
inline bool wait_readable(int fd, int timeout_ms, const std::string& label) {
  pollfd p{fd, POLLIN, 0};
  const int r = ::poll(&p, 1, timeout_ms);
  if (r < 0) {
    if (errno == EINTR) return false;
    throw std::system_error(errno, std::generic_category(), label + ": poll failed");
  }
  return r > 0;
}

}  // namespace cubecal::acquire::detail
