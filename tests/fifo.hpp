// Test support: what a writer puts into a FIFO (outputs written into FIFOs
// rather than replaced: atomic_file and the commands' output checks).
#pragma once
#include <fcntl.h>
#include <unistd.h>

#include <string>

namespace cubecal::test {

// What a writer puts into the FIFO `p`, read without ever blocking: ends at
// the writer's close, or after 20 s when no writer comes (a test that fails
// rather than hangs).
inline std::string drain_fifo(const std::string& p) {
  const int fd = ::open(p.c_str(), O_RDONLY | O_NONBLOCK);
  if (fd < 0) return "(cannot open the FIFO)";
  std::string got;
  bool writer = false;
  char buf[4096];
  for (int i = 0; i < 2000; ++i) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n > 0) {
      got.append(buf, static_cast<std::size_t>(n));
      writer = true;
      continue;
    }
    if (n < 0) writer = true;  // EAGAIN: a writer, no data yet
    if (n == 0 && writer) break;
    ::usleep(10000);
  }
  ::close(fd);
  return got;
}

}  // namespace cubecal::test
