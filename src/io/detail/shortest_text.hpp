// Small text helpers the readers share for their messages.
#pragma once
#include <charconv>
#include <string>

namespace cubecal::io::detail {

// The shortest text that reads back as the same double (how a time stamp or
// a value is normally written in the file).
inline std::string shortest_text(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

// ASCII lower case (column names compared without regard to case).
inline std::string lower_case(std::string s) {
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return s;
}

}  // namespace cubecal::io::detail
