// printable_text.hpp: control bytes and malformed UTF-8 escaped as \xNN.
#include "cubecal/printable_text.hpp"

#include <cstdio>

namespace cubecal {

namespace {

// Length of the well-formed UTF-8 sequence of more than one byte at s[i]; 0 if none.
std::size_t utf8_sequence(std::string_view s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  const std::size_t len = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
  if (len == 0 || i + len > s.size()) return 0;
  for (std::size_t k = 1; k < len; ++k) {
    if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return 0;
  }
  const auto c1 = static_cast<unsigned char>(s[i + 1]);
  // Overlong forms, UTF-16 surrogates and code points past U+10FFFF.
  if ((c == 0xe0 && c1 < 0xa0) || (c == 0xed && c1 >= 0xa0) || (c == 0xf0 && c1 < 0x90) || (c == 0xf4 && c1 >= 0x90))
    return 0;
  return len;
}

bool is_control(unsigned char c) { return c < 0x20 || c == 0x7f; }

// `text` with the bytes that `keep` refuses written as \xNN: the bytes of a
// malformed UTF-8 sequence always, ASCII bytes when keep(c) is false.
template <class Keep>
std::string escaped(std::string_view text, Keep keep) {
  std::string out;
  std::size_t clean = 0;  // text[0, clean) is known to need no escape
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80 && keep(c)) {
      ++i;
      continue;
    }
    if (c >= 0x80) {
      if (const std::size_t len = utf8_sequence(text, i)) {
        i += len;
        continue;
      }
    }
    out.append(text.data() + clean, i - clean);
    char buf[8];
    std::snprintf(buf, sizeof buf, "\\x%02x", static_cast<unsigned>(c));
    out += buf;
    clean = ++i;
  }
  if (clean == 0) return std::string(text);
  out.append(text.data() + clean, text.size() - clean);
  return out;
}

}  // namespace

std::string printable_text(std::string_view text) {
  return escaped(text, [](unsigned char c) { return !is_control(c); });
}

std::string utf8_text(std::string_view text) {
  return escaped(text, [](unsigned char) { return true; });
}

}  // namespace cubecal
