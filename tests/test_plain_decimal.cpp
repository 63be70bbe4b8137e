// The plain-decimal fast path of the text readers (src/io/detail/
// plain_decimal.hpp) against fast_float, the parser it stands in for: every
// text it takes must give fast_float's value to the bit and end where
// fast_float ends; the logger forms must be taken, the rest left alone.
#include <fast_float/fast_float.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>

#include "../src/io/detail/plain_decimal.hpp"

namespace {

using cubecal::io::detail::plain_decimal;

std::uint64_t bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

// Taken: the value and end fast_float gives. Returns whether it was taken.
bool check(const std::string& text) {
  const char* b = text.data();
  const char* e = b + text.size();
  double v = 12345.0;
  const char* end = plain_decimal(b, e, v);
  if (end == nullptr) return false;
  double ref = -1.0;
  const auto r = fast_float::from_chars(b, e, ref);
  EXPECT_EQ(r.ec, std::errc()) << "'" << text << "'";
  EXPECT_EQ(end, r.ptr) << "'" << text << "'";
  EXPECT_EQ(bits(v), bits(ref)) << "'" << text << "': " << v << " vs " << ref;
  return true;
}

TEST(PlainDecimal, TakesTheLoggerFormsWithFastFloatsValue) {
  for (const char* t : {"0.00,", "-0.005415645,", "0.009615531\n", "25.000\n", "215.8138,", "-94.42416", "0",
                        "-0", "-0.0", "7", "9007199254740992", "0.1", "1.7976931348",
                        "450359962737.0497", "0.000000000000000001", "0x10"}) {
    EXPECT_TRUE(check(t)) << t;
  }
}

TEST(PlainDecimal, LeavesEverythingElseToTheFullParser) {
  for (const char* t : {"+1.5", "1e5", "1.5E-3", ".5", "5.", "-", "-.", "", "inf", "nan", "-inf",
                        "9007199254740993", "4503599627370497.5",  // above 2^53
                        "12345678901234567890",     // 20 digits
                        "1.2345678901234567890",    // 20 digits
                        "1.2.3", " 1"}) {
    double v = 0.0;
    EXPECT_EQ(plain_decimal(t, t + std::strlen(t), v), nullptr) << "'" << t << "'";
  }
}

// Random texts of every shape near the fast path's edges: signs, leading
// zeros, 0-21 digits on each side of the point, exponents, and what may
// follow a field. Seeded; 2 million texts.
TEST(PlainDecimal, RandomTextsEqualFastFloatToTheBit) {
  std::mt19937_64 rng(20261127);
  const auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<std::uint64_t>(n)); };
  const char* const follow[] = {"", ",", "\n", "\r\n", ";", "\t", " ", "x", "e", "E5", ".", "5", "e-3", "0,"};
  std::size_t taken = 0, total = 0;
  for (int i = 0; i < 2000000; ++i) {
    std::string t;
    const int sign = pick(8);
    if (sign == 0) t += '-';
    if (sign == 1) t += '+';
    const int zeros = pick(5) == 0 ? pick(4) : 0;
    t.append(static_cast<std::size_t>(zeros), '0');
    const int whole = pick(6) == 0 ? pick(22) : pick(4);
    for (int k = 0; k < whole; ++k) t += static_cast<char>('0' + pick(10));
    if (pick(6) != 0) {
      t += '.';
      const int frac = pick(4) == 0 ? pick(22) : pick(12);
      for (int k = 0; k < frac; ++k) t += static_cast<char>('0' + (pick(3) == 0 ? 9 : pick(10)));
    }
    t += follow[pick(static_cast<int>(std::size(follow)))];
    taken += check(t) ? 1 : 0;
    ++total;
  }
  // Most random shapes are plain decimals within 19 digits.
  EXPECT_GT(taken, total / 3) << taken << " of " << total;
}

// Every prefix of a field ends somewhere a chunk or window may cut it: the
// fast path reads no byte at or past `end`.
TEST(PlainDecimal, ReadsNothingPastTheEnd) {
  const std::string text = "-12.3456789012345678,";
  for (std::size_t len = 0; len <= text.size(); ++len) {
    const std::string piece = text.substr(0, len);
    auto* heap = new char[len == 0 ? 1 : len];  // exactly len bytes: the sanitizers see a read past it
    std::memcpy(heap, piece.data(), len);
    double v = 0.0;
    const char* end = plain_decimal(heap, heap + len, v);
    if (end != nullptr) {
      double ref = 0.0;
      const auto r = fast_float::from_chars(heap, heap + len, ref);
      EXPECT_EQ(end - heap, r.ptr - heap) << piece;
      EXPECT_EQ(bits(v), bits(ref)) << piece;
    }
    delete[] heap;
  }
}

}  // namespace
