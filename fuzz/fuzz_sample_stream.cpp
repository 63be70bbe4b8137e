// libFuzzer target: the chunked sample source (io::SampleStream) on arbitrary
// bytes. The first byte chooses text or raw frames of a few layouts, the
// rate/time options and a small piece size (so that pieces split the input
// anywhere); the rest is the file. Every piece must hold equally long,
// finite columns; the only errors allowed are the documented ones.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "cubecal/io/sample_stream.hpp"
#include "error_check.hpp"
#include "memory_file.hpp"

namespace {

using namespace cubecal;

constexpr const char* kLayouts[] = {"int16le,int16le,int16le", "float32be,uint8", "float64le", "int32be,uint64le,int8"};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const unsigned mode = data[0];
  const std::string bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  const fuzz::MemoryFile file(bytes);
  io::SeriesOptions sopt;
  sopt.rate_hz = (mode & 2u) != 0 ? 100.0 : 0.0;
  if ((mode & 4u) != 0) sopt.time_col = "1";
  if ((mode & 1u) != 0) sopt.binary = io::parse_raw_layout(kLayouts[(mode >> 4) & 3u], (mode >> 6) & 3u);
  const std::size_t piece = (mode & 8u) != 0 ? 64 : 4096;
  fuzz::expect_clean([&] {
    const auto s = io::SampleStream::open(file.path(), sopt, piece);
    io::SampleChunk c;
    while (s->next(c)) {
      if (c.channels.size() != s->names().size()) fuzz::finding("stream", "channels/names");
      for (const auto& col : c.channels) {
        if (col.size() != c.rows()) fuzz::finding("stream", "columns of different lengths");
        for (double v : col)
          if (!std::isfinite(v)) fuzz::finding("stream", "non-finite value returned");
      }
    }
  });
  return 0;
}
