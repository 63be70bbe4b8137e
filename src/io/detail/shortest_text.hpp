// Small text helpers the readers share for their messages.
#pragma once
#include <charconv>
#include <cmath>
#include <string>

namespace cubecal::io::detail {

// The shortest text that reads back as the same double, or within one unit
// in its last place: how a time stamp or a value is normally written in the
// file, without the noise of a conversion (a ULog stamp of 20326716 us is the
// double 20.326715999999998, shown as 20.326716).
inline std::string shortest_text(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string exact(buf, r.ptr);
  if (!std::isfinite(v) || v == 0.0) return exact;
  const double ulp = std::nextafter(std::fabs(v), HUGE_VAL) - std::fabs(v);
  for (int digits = 1; digits < 17; ++digits) {
    const auto g = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, digits);
    double back = 0.0;
    std::from_chars(buf, g.ptr, back);
    if (std::fabs(back - v) > ulp) continue;
    const auto length = static_cast<std::size_t>(g.ptr - buf);
    return length < exact.size() ? std::string(buf, g.ptr) : exact;  // (not 1e+02 for 100)
  }
  return exact;
}

// ASCII lower case (column names compared without regard to case).
inline std::string lower_case(std::string s) {
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return s;
}

}  // namespace cubecal::io::detail
