// libFuzzer target: the text-line framer of `cubecal record`
// (acquire::LineFramer) on arbitrary bytes arriving in arbitrary pieces, as
// reads from a serial port or a socket split them. The first byte chooses
// the options (delimiter, --columns, a short longest line), the second seeds
// the piece sizes; the rest is the stream. Checked: the layout comes once,
// before any sample; every sample has one finite value per column, and its
// chunk fields (one line, comma-separated) read back as those values; no
// byte is handed on twice; and, with the longest line beyond the input, the
// same samples and rejects whatever the pieces (the whole stream at once).
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <fast_float/fast_float.h>

#include "cubecal/acquire/line_framer.hpp"
#include "error_check.hpp"
#include "handed_log.hpp"

namespace {

using namespace cubecal;

// The framer's output, checked as it comes, and logged for comparison.
class Checker final : public acquire::SampleHandler {
 public:
  void on_layout(const std::vector<std::string>& names) override {
    if (layouts_++ > 0) fuzz::finding("line framer", "layout handed on twice");
    if (names.empty()) fuzz::finding("line framer", "layout without columns");
    columns_ = names.size();
    log_.layout(columns_);
  }
  void on_sample(std::string_view fields, std::span<const double> values) override {
    if (layouts_ == 0) fuzz::finding("line framer", "sample before the layout");
    if (values.size() != columns_) fuzz::finding("line framer", "sample with a value count other than the layout's");
    if (fields.find_first_of("\r\n") != std::string_view::npos)
      fuzz::finding("line framer", "line end inside a sample");
    std::size_t i = 0;
    for (std::size_t b = 0;; ++i) {
      const std::size_t e = std::min(fields.find(',', b), fields.size());
      std::string_view f = fields.substr(b, e - b);
      while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.remove_prefix(1);
      while (!f.empty() && (f.back() == ' ' || f.back() == '\t')) f.remove_suffix(1);
      if (!f.empty() && f.front() == '+') f.remove_prefix(1);
      // Read back as the chunk readers read it (io/delimited_reader: fast_float,
      // which takes a value below the smallest double as zero where
      // std::from_chars reports it out of range).
      double v = 0;
      const auto r = fast_float::from_chars(f.data(), f.data() + f.size(), v);
      if (i >= values.size() || r.ec != std::errc() || r.ptr != f.data() + f.size() || !std::isfinite(values[i]) ||
          v != values[i])
        fuzz::finding("line framer", "chunk fields do not read back as the sample's values");
      if (e == fields.size()) break;
      b = e + 1;
    }
    if (i + 1 != values.size()) fuzz::finding("line framer", "chunk field count differs from the value count");
    log_.sample(fields, fields.size());
  }
  void on_reject(std::string_view reason, std::string_view data, bool binary) override {
    if (reason.empty()) fuzz::finding("line framer", "reject without a reason");
    if (binary) fuzz::finding("line framer", "text reject marked binary");
    log_.reject(reason, data);
  }
  std::size_t handed() const { return log_.handed; }
  const std::string& log() const { return log_.text; }

 private:
  std::size_t layouts_ = 0, columns_ = 0;
  fuzz::HandedLog log_;
};

acquire::LineFramerOptions options(unsigned mode) {
  acquire::LineFramerOptions o;
  constexpr char kDelims[] = {0, ',', '\t', ';', ' ', 0, 0, 0};
  if (kDelims[mode & 7u] != 0) o.delimiter = kDelims[mode & 7u];
  if ((mode & 8u) != 0) o.columns = {"t", "gx", "gy"};
  if ((mode & 16u) != 0) o.max_line = 24;
  return o;
}

// Feeds `stream` in pieces of 1 to 32 bytes drawn from `seed` (or at once
// when seed is 0), then ends it; returns the log.
std::string run(std::string_view stream, unsigned mode, unsigned seed, std::size_t& handed) {
  acquire::LineFramer framer(options(mode));
  Checker c;
  std::uint32_t x = seed * 2654435761u + 1u;
  std::size_t at = 0;
  while (at < stream.size()) {
    std::size_t n = stream.size() - at;
    if (seed != 0) {
      x ^= x << 13;
      x ^= x >> 17;
      x ^= x << 5;
      n = std::min<std::size_t>(n, 1 + x % 32);
    }
    framer.feed(stream.substr(at, n), c);
    at += n;
  }
  framer.finish(c);
  if (!framer.partial().empty()) fuzz::finding("line framer", "bytes held after finish");
  handed = c.handed();
  return c.log();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const unsigned mode = data[0];
  const unsigned seed = data[1];
  const std::string_view stream(reinterpret_cast<const char*>(data + 2), size - 2);
  std::string pieces, whole;
  bool pieces_done = false, whole_done = false;
  std::size_t handed = 0, handed_whole = 0;
  fuzz::expect_clean([&] {
    pieces = run(stream, mode, seed | 1u, handed);
    pieces_done = true;
  });
  if (pieces_done && handed > stream.size()) fuzz::finding("line framer", "more bytes handed on than received");
  fuzz::expect_clean([&] {
    whole = run(stream, mode, 0, handed_whole);
    whole_done = true;
  });
  // A line longer than max_line is cut where the pieces happen to end: the
  // comparison holds when no line can reach it.
  const bool long_lines = (mode & 16u) != 0;
  if (!long_lines && pieces_done != whole_done)
    fuzz::finding("line framer", "an error depends on how the bytes were split");
  if (!long_lines && pieces_done && whole_done && pieces != whole)
    fuzz::finding("line framer", "samples or rejects depend on how the bytes were split");
  return 0;
}
