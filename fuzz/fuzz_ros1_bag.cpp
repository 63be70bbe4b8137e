// libFuzzer target: the ROS 1 bag reader. The input is a file as
// read_series gets it: a bag (by its magic) is parsed record by record,
// its chunks inflated (none, bz2, lz4), the sensor messages of the chosen
// topics decoded and timed. Seeds: fuzz/corpus/ros1_bag (a small bag of
// uncompressed, bz2 and lz4 chunks) and the real recordings in
// ../shared/data/rosbag/ros1 (run.sh adds them when present).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "cubecal/io/ros1_bag.hpp"
#include "cubecal/io/series.hpp"
#include "error_check.hpp"
#include "memory_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cubecal;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  fuzz::expect_clean([&] { (void)io::parse_ros1_bag(bytes, "fuzz.bag"); });
  const fuzz::MemoryFile file(bytes);
  fuzz::expect_clean([&] {
    io::SeriesOptions opt;
    opt.table.threads = 1;
    opt.gaps = io::GapPolicy::split;
    (void)io::read_series(file.path(), opt);
  });
  return 0;
}
