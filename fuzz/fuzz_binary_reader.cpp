// libFuzzer target: the binary readers on arbitrary bytes. The first byte
// chooses the reader and its options: NumPy .npy (the magic is prepended
// when the input lacks it, so the fuzzer spends its time on the header and
// the data) or raw frames of a layout picked from a few, with a header of
// 0..7 bytes; the rest is the file, read in memory (read_npy,
// read_raw_binary) and through read_series.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "../src/io/detail/npy_reader.hpp"
#include "cubecal/io/raw_binary_reader.hpp"
#include "cubecal/io/series.hpp"
#include "error_check.hpp"
#include "memory_file.hpp"

namespace {

using namespace cubecal;

void check_table(const io::Table& t) {
  if (t.names.size() != t.data.size() || t.indices.size() != t.data.size()) fuzz::finding("table", "names/data");
  for (const auto& c : t.data) {
    if (c.size() != t.rows()) fuzz::finding("table", "columns of different lengths");
    for (double v : c) {
      if (!std::isfinite(v)) fuzz::finding("table", "non-finite value returned");
    }
  }
}

constexpr const char* kLayouts[] = {"int16le,int16le,int16le", "float32be,uint8", "float64le", "int32be,uint64le,int8"};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const unsigned mode = data[0];
  std::string bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  const bool npy = (mode & 1u) == 0;
  io::SeriesOptions sopt;
  sopt.rate_hz = (mode & 2u) != 0 ? 100.0 : 0.0;
  if ((mode & 4u) != 0) sopt.time_col = "1";
  sopt.gaps = (mode & 8u) != 0 ? io::GapPolicy::split : io::GapPolicy::error;
  if (npy) {
    if (!io::is_npy(bytes)) bytes.insert(0, "\x93NUMPY", 6);
    fuzz::expect_clean([&] { check_table(io::read_npy(bytes, "fuzz.npy")); });
  } else {
    sopt.binary = io::parse_raw_layout(kLayouts[(mode >> 4) & 3u], (mode >> 6) & 3u);
    fuzz::expect_clean([&] { check_table(io::read_raw_binary(bytes, "fuzz.bin", sopt.binary)); });
  }
  const fuzz::MemoryFile file(bytes);
  fuzz::expect_clean([&] {
    const io::Series s = io::read_series(file.path(), sopt);
    if (!(s.rate_hz > 0.0) || !std::isfinite(s.rate_hz)) fuzz::finding("series", "rate not positive and finite");
    for (const auto& c : s.channels) {
      for (double v : c) {
        if (!std::isfinite(v)) fuzz::finding("series", "non-finite value returned");
      }
    }
  });
  return 0;
}
