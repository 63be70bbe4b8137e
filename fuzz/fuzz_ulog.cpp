// libFuzzer target: the PX4 ULog reader. The input is a file as
// read_series gets it: a log (by its magic) is parsed message by message,
// its formats laid out, the sensor topics decoded and timed. Seeds:
// fuzz/corpus/ulog (a small log with nested types, padding, dropouts, sync,
// logging and remove messages) and the real logs in ../shared/data/px4
// (run.sh adds them when present).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "cubecal/io/series.hpp"
#include "cubecal/io/ulog.hpp"
#include "error_check.hpp"
#include "memory_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cubecal;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  fuzz::expect_clean([&] { (void)io::parse_ulog(bytes, "fuzz.ulg"); });
  const fuzz::MemoryFile file(bytes);
  for (const char* topics : {"", "vehicle_magnetometer"}) {
    fuzz::expect_clean([&] {
      io::SeriesOptions opt;
      opt.table.threads = 1;
      opt.gaps = io::GapPolicy::split;
      opt.min_samples = 2;
      if (*topics != '\0') opt.topics = {"sensor_combined", topics};
      (void)io::read_series(file.path(), opt);
    });
  }
  return 0;
}
