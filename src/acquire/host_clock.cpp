// Host receive stamps (host_clock.hpp).
#include "cubecal/acquire/host_clock.hpp"

#include <charconv>

namespace cubecal::acquire {

HostStamp host_now() noexcept {
  HostStamp s;
  ::clock_gettime(CLOCK_MONOTONIC, &s.mono);
  ::clock_gettime(CLOCK_REALTIME, &s.utc);
  return s;
}

std::size_t format_seconds(const timespec& t, char* out) noexcept {
  char* p = out;
  long long sec = static_cast<long long>(t.tv_sec);
  if (sec < 0) {  // never for these clocks; kept exact anyway
    *p++ = '-';
    sec = -sec;
  }
  p = std::to_chars(p, out + 24, sec).ptr;
  *p++ = '.';
  long ns = t.tv_nsec;
  for (int i = 8; i >= 0; --i) {
    p[i] = static_cast<char>('0' + ns % 10);
    ns /= 10;
  }
  p += 9;
  return static_cast<std::size_t>(p - out);
}

std::string stamp_prefix(const HostStamp& s) {
  char buf[80];
  std::size_t n = format_seconds(s.mono, buf);
  buf[n++] = ',';
  n += format_seconds(s.utc, buf + n);
  buf[n++] = ',';
  return std::string(buf, n);
}

}  // namespace cubecal::acquire
