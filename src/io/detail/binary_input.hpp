// Input that is not delimited text. A binary file handed to a text reader
// (an executable, an archive, a bag, a file of zeros, UTF-16 text) is refused
// at its start, saying what it seems to be; a binary byte that the parser
// meets further on (a fault in its line) is reported as such. Neither echoes
// the bytes themselves.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

namespace cubecal::io::detail {

// How much of the start of a text is examined (NUL bytes, signatures).
inline constexpr std::size_t kTextProbeBytes = std::size_t{1} << 16;

// Throws InputError when `head`, the first bytes of a file's text (at most
// kTextProbeBytes are looked at), holds a NUL byte or starts with the
// signature of a binary format. `decompressed`: the text was inflated from
// gzip (offsets are then offsets in the decompressed text).
void check_text_start(std::string_view head, const std::string& file, bool decompressed);

// The first byte in [begin, end) that text does not hold: NUL and the C0
// controls other than tab, line feed, vertical tab, form feed and carriage
// return, and DEL. Null when there is none.
const char* find_binary_byte(const char* begin, const char* end) noexcept;

// The error for binary byte `*where` of `text` found at line:column.
[[noreturn]] void throw_binary_byte(std::string_view text, const char* where, const std::string& file, std::size_t line,
                                    std::size_t column, std::size_t offset_base);

}  // namespace cubecal::io::detail
