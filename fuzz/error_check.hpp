// Fuzzing support: runs one library call and lets through only the errors
// the library documents for bad input (InputError, UsageError), each a
// single printable line, as the CLI prints it. Anything else (another
// exception type, a message with raw bytes or a line break, a crash) is a
// finding: libFuzzer stops on the abort and saves the input.
#pragma once
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "cubecal/error.hpp"

namespace cubecal::fuzz {

// Printable ASCII, or bytes of a well-formed UTF-8 sequence; no control bytes.
inline bool printable_line(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      if (c < 0x20 || c == 0x7f) return false;
      ++i;
      continue;
    }
    const std::size_t len = c >= 0xf0 && c < 0xf5 ? 4 : c >= 0xe0 ? 3 : c >= 0xc2 && c < 0xe0 ? 2 : 0;
    if (len == 0 || i + len > s.size()) return false;
    for (std::size_t k = 1; k < len; ++k) {
      if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return false;
    }
    i += len;
  }
  return true;
}

[[noreturn]] inline void finding(const char* what, std::string_view message) {
  std::fprintf(stderr, "cubecal fuzz finding: %s: %.*s\n", what, static_cast<int>(message.size()), message.data());
  std::abort();
}

template <class Call>
void expect_clean(const Call& call) {
  try {
    call();
  } catch (const InputError& e) {
    if (!printable_line(e.what())) finding("InputError message not one printable line", e.what());
  } catch (const UsageError& e) {
    if (!printable_line(e.what())) finding("UsageError message not one printable line", e.what());
  }
}

}  // namespace cubecal::fuzz
