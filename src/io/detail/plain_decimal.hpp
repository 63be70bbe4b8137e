// Internal: the numbers loggers write most, [-]digits.digits with at most 19
// digits, parsed without the generality of a full float parser.
//
// The value is Clinger's fast path (Clinger, PLDI 1990; the first step of
// fast_float and of every correctly rounding strtod): the digits as an
// integer w <= 2^53 and a power of ten 10^k with k <= 22 are both exact
// doubles, so w / 10^k is one correctly rounded IEEE division. A correctly
// rounded result is unique, so it is the value fast_float gives for the same
// text, bit for bit (test_plain_decimal checks this over millions of texts).
// Anything else -- an exponent, a '+', no digit before or after the point,
// more than 19 digits, w above 2^53, "inf" or "nan" -- is left to the caller
// (nullptr), which hands it to fast_float.
//
// The eight-digit step is the SWAR form of Lemire's "Fast number parsing"
// (Software: Practice and Experience, 2021): one 64-bit load, a test that
// all eight bytes are digits, and three multiplications instead of eight
// dependent multiply-adds.
#pragma once

#include <bit>
#include <cfloat>
#include <cstdint>
#include <cstring>

namespace cubecal::io::detail {

inline bool is_digit(char c) noexcept { return static_cast<unsigned char>(c - '0') < 10; }

// The eight bytes of v, loaded little-endian, are all '0'..'9'.
inline bool eight_digits(std::uint64_t v) noexcept {
  return ((v & 0xF0F0F0F0F0F0F0F0) | (((v + 0x0606060606060606) & 0xF0F0F0F0F0F0F0F0) >> 4)) == 0x3333333333333333;
}

// The value of eight digit bytes, the first the most significant.
inline std::uint32_t eight_digit_value(std::uint64_t v) noexcept {
  v -= 0x3030303030303030;
  v = (v * 10) + (v >> 8);  // pairs
  v = (((v & 0x000000FF000000FF) * (100 + (1000000ULL << 32))) +
       (((v >> 16) & 0x000000FF000000FF) * (1 + (10000ULL << 32)))) >>
      32;
  return static_cast<std::uint32_t>(v);
}

// Parses [-]d+(.d+)? at p; the end of the number, or nullptr when the text is
// not of that plain form (or beyond the fast path): the caller then parses it
// in full. What follows the number is the caller's to check; a following
// 'e'/'E', '.' or digit (an exponent, or digits beyond 19) gives nullptr.
inline const char* plain_decimal(const char* p, const char* end, double& out) noexcept {
#if !defined(FLT_EVAL_METHOD) || (FLT_EVAL_METHOD != 0 && FLT_EVAL_METHOD != 1)
  // Division in a wider format (x87) would round twice: not the fast path.
  (void)p;
  (void)end;
  (void)out;
  return nullptr;
#endif
  static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                      1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  const char* s = p;
  const bool negative = s < end && *s == '-';
  if (negative) ++s;
  const char* const first = s;
  std::uint64_t w = 0;
  // At most 19 digits in all: w stays below 10^19 < 2^64.
  while (s < end && is_digit(*s) && s - first < 19) w = 10 * w + static_cast<unsigned>(*s++ - '0');
  const auto int_digits = static_cast<std::size_t>(s - first);
  if (int_digits == 0) return nullptr;
  std::size_t frac = 0;
  if (s < end && *s == '.') {
    const char* const f0 = ++s;
    std::size_t room = 19 - int_digits;
    // The eight-digit step reads the bytes as a little-endian word; a
    // big-endian machine (SPARC LEON flight computers) takes them one by one.
    while (std::endian::native == std::endian::little && room >= 8 && end - s >= 8) {
      std::uint64_t chunk;
      std::memcpy(&chunk, s, 8);
      if (!eight_digits(chunk)) break;
      w = w * 100000000 + eight_digit_value(chunk);
      s += 8;
      room -= 8;
    }
    while (room > 0 && s < end && is_digit(*s)) {
      w = 10 * w + static_cast<unsigned>(*s++ - '0');
      --room;
    }
    frac = static_cast<std::size_t>(s - f0);
    if (frac == 0) return nullptr;
  }
  if (s < end && (is_digit(*s) || *s == '.' || *s == 'e' || *s == 'E')) return nullptr;
  if (w > (std::uint64_t{1} << 53)) return nullptr;
  double v = static_cast<double>(w);
  if (frac > 0) v /= kPow10[frac];  // frac <= 19 < 23: 10^frac is exact
  out = negative ? -v : v;
  return s;
}

}  // namespace cubecal::io::detail
