// The plain-decimal fast path of the text readers (src/io/detail/
// plain_decimal.hpp) against fast_float, the parser it stands in for: every
// text it takes must give fast_float's value to the bit and end where
// fast_float ends; the logger forms must be taken, the rest left alone.
#include <fast_float/fast_float.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../src/io/detail/plain_decimal.hpp"
#include "cubecal/io/delimited_reader.hpp"

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
  for (const char* t :
       {"0.00,", "-0.005415645,", "0.009615531\n", "25.000\n", "215.8138,", "-94.42416", "0", "-0", "-0.0", "7",
        "9007199254740992", "0.1", "1.7976931348", "450359962737.0497", "0.000000000000000001", "0x10"}) {
    EXPECT_TRUE(check(t)) << t;
  }
}

TEST(PlainDecimal, LeavesEverythingElseToTheFullParser) {
  for (const char* t : {"+1.5", "1e5", "1.5E-3", ".5", "5.", "-", "-.", "", "inf", "nan", "-inf", "9007199254740993",
                        "4503599627370497.5",     // above 2^53
                        "12345678901234567890",   // 20 digits
                        "1.2345678901234567890",  // 20 digits
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

// The reader end to end: a table whose fields are written in every way a
// logger or a spreadsheet writes numbers (fixed, shortest round trip,
// exponent, a leading '+', padding, more than 19 digits) reads back each
// field as fast_float reads it alone, whichever path the row takes (the
// plain-decimal fast path, fast_float, or the general rules). Large enough
// to be cut into chunks for both threads.
TEST(PlainDecimal, ReaderGivesEveryFieldFastFloatsValue) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_int_distribution<int> form(0, 7), scale(-8, 8);
  std::string text = "a,b,c\n";
  std::vector<std::string> fields;
  char buf[64];
  for (int row = 0; row < 60000; ++row) {
    for (int c = 0; c < 3; ++c) {
      const double v = normal(rng) * std::pow(10.0, scale(rng));
      switch (form(rng)) {
        case 0: std::snprintf(buf, sizeof buf, "%.17g", v); break;
        case 1: std::snprintf(buf, sizeof buf, "%.6f", v); break;
        case 2: std::snprintf(buf, sizeof buf, "%.9e", v); break;
        case 3: std::snprintf(buf, sizeof buf, "%+.5f", v); break;
        case 4: std::snprintf(buf, sizeof buf, "%.25f", v); break;
        case 5: std::snprintf(buf, sizeof buf, "%.0f", v); break;
        case 6: std::snprintf(buf, sizeof buf, "%.10g", v); break;
        default: std::snprintf(buf, sizeof buf, "%.3f", v); break;
      }
      fields.emplace_back(buf);
      if (c > 0) text += row % 97 == 5 ? ", " : ",";
      text += buf;
    }
    text += '\n';
  }
  const cubecal::io::Table t = cubecal::io::parse_table(text, "mixed.csv");
  ASSERT_EQ(t.rows(), 60000u);
  std::size_t k = 0, differ = 0;
  for (std::size_t row = 0; row < t.rows(); ++row)
    for (std::size_t c = 0; c < 3; ++c, ++k) {
      const std::string& f = fields[k];
      const char* b = f.data() + (f[0] == '+' ? 1 : 0);
      double ref = 0.0;
      (void)fast_float::from_chars(b, f.data() + f.size(), ref);
      if (bits(t.data[c][row]) != bits(ref) && ++differ <= 5)
        ADD_FAILURE() << "row " << row << " column " << c << " '" << f << "': " << t.data[c][row] << " vs " << ref;
    }
  EXPECT_EQ(differ, 0u);
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
