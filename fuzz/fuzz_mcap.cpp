// libFuzzer target: the MCAP reader. The input is a file as read_series
// gets it: an MCAP file (by its magic) is walked record by record, its
// chunks inflated (none, zstd, lz4) and CRC-checked, the CDR sensor
// messages of the chosen topics decoded and timed. Seeds: fuzz/corpus/mcap
// (small files of uncompressed, zstd and lz4 chunks, big- and little-endian
// CDR, with and without a summary) and the real recording in
// ../shared/data/rosbag/ros2-mcap (run.sh adds it when present).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "cubecal/io/mcap.hpp"
#include "cubecal/io/series.hpp"
#include "error_check.hpp"
#include "memory_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cubecal;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  fuzz::expect_clean([&] { (void)io::parse_mcap(bytes, "fuzz.mcap"); });
  const fuzz::MemoryFile file(bytes);
  fuzz::expect_clean([&] {
    io::SeriesOptions opt;
    opt.table.threads = 1;
    opt.gaps = io::GapPolicy::split;
    (void)io::read_series(file.path(), opt);
  });
  fuzz::expect_clean([&] {
    io::SeriesOptions opt;
    opt.table.threads = 1;
    opt.gaps = io::GapPolicy::split;
    opt.topics = {"/temp", "/imu"};
    opt.time_col = "record";
    (void)io::read_series(file.path(), opt);
  });
  return 0;
}
