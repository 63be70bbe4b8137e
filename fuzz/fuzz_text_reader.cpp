// libFuzzer target: the delimited-text reader on arbitrary bytes, in memory
// (parse_layout, parse_table) and through a file (read_series, which maps
// the file and checks the time stamps). The first byte chooses the options;
// the rest is the file.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/io/series.hpp"
#include "error_check.hpp"
#include "memory_file.hpp"

namespace {

using namespace cubecal;

// What the reader promises for the data it returns.
void check_table(const io::Table& t) {
  if (t.names.size() != t.data.size() || t.indices.size() != t.data.size()) fuzz::finding("table", "names/data");
  for (const auto* cols : {&t.data, &t.extra}) {
    for (const auto& c : *cols) {
      if (c.size() != t.rows()) fuzz::finding("table", "columns of different lengths");
      for (double v : c) {
        if (!std::isfinite(v)) fuzz::finding("table", "non-finite value returned");
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const unsigned mode = data[0];
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);

  io::TableOptions topt;
  topt.skip_rows = mode & 3u;
  topt.threads = 1;
  if ((mode & 4u) != 0) topt.columns = {"2"};
  if ((mode & 8u) != 0) topt.extra_columns = {"1"};
  fuzz::expect_clean([&] { (void)io::parse_layout(text, "fuzz.csv", topt); });
  fuzz::expect_clean([&] { check_table(io::parse_table(text, "fuzz.csv", topt)); });

  io::SeriesOptions sopt;
  sopt.table.skip_rows = topt.skip_rows;
  sopt.table.threads = 1;
  sopt.rate_hz = (mode & 16u) != 0 ? 100.0 : 0.0;
  sopt.gaps = (mode & 32u) != 0 ? io::GapPolicy::split : io::GapPolicy::error;
  if ((mode & 64u) != 0) sopt.time_col = "1";
  if ((mode & 128u) != 0) sopt.lsb = {131.0};
  const fuzz::MemoryFile file(text);
  fuzz::expect_clean([&] {
    const io::Series s = io::read_series(file.path(), sopt);
    if (!(s.rate_hz > 0.0) || !std::isfinite(s.rate_hz)) fuzz::finding("series", "rate not positive and finite");
    if (s.segments.empty()) fuzz::finding("series", "no segment");
    for (const auto& c : s.channels) {
      if (c.size() != s.samples()) fuzz::finding("series", "channels of different lengths");
      for (double v : c) {
        if (!std::isfinite(v)) fuzz::finding("series", "non-finite value returned");
      }
    }
  });
  return 0;
}
