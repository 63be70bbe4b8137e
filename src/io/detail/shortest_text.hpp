// Small text helpers the readers share for their messages.
#pragma once
#include <algorithm>
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

// `v` with to_chars in `fmt` at `precision`.
inline std::string number_text(double v, std::chars_format fmt, int precision) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, fmt, precision);
  return std::string(buf, r.ptr);
}

// A duration (a gap, an interval) with four significant digits, without
// switching to exponents for long gaps.
inline std::string duration_text(double v) {
  const double mag = std::floor(std::log10(std::max(std::fabs(v), 1e-9)));
  return number_text(v, std::chars_format::fixed, static_cast<int>(std::clamp(3.0 - mag, 0.0, 9.0)));
}

// A sampling period or rate from 1/median(dt), with six significant digits:
// rounding noise in the last digits is not worth showing.
inline std::string period_text(double v) { return number_text(v, std::chars_format::general, 6); }

// ASCII lower case (column names compared without regard to case).
inline std::string lower_case(std::string s) {
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return s;
}

}  // namespace cubecal::io::detail
