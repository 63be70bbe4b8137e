#include "memory_budget.hpp"

#include <fmt/format.h>

#include "cubecal/pipeline/dev_stream.hpp"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <exception>
#include <cmath>

#include "cubecal/error.hpp"
#include "cubecal/io/message_log.hpp"
#include "cubecal/io/recording.hpp"
#include "cubecal/io/ulog.hpp"
#include "cubecal/io/recording_manifest.hpp"
#include "cubecal/io/sample_stream.hpp"
#include "progress.hpp"

namespace cubecal::cli {

void add_memory_options(CLI::App& cmd, MemoryOptions& opt) {
  cmd.add_flag("--stream", opt.stream,
               "Read the record in pieces and compute in one pass with bounded memory (adev, oadev, hdev, "
               "ohdev; factors beyond the window bound at a stride). Chosen by itself when reading the file "
               "whole would exceed --memory");
  cmd.add_option("--memory", opt.memory,
                 "Memory budget, e.g. 2G or 512M (default: half the physical memory): a larger record is "
                 "streamed, and the stream's window bound follows from it");
  cmd.add_option("--window", opt.window,
                 "Stream's window bound in samples, a power of two >= 16 (default: the largest --memory allows, "
                 "up to 65536): factors whose terms span at most this many samples are exact (stride 1), "
                 "larger ones partially overlapping; a smaller bound is faster");
}

std::size_t stream_window(const MemoryOptions& opt, std::size_t budget, std::size_t channels,
                          std::size_t samples_hint) {
  if (opt.window == 0) {
    const std::size_t bound = pipeline::window_bound_for(budget, channels);
    if (samples_hint == 0) return bound;
    return std::min(bound, std::max<std::size_t>(std::bit_ceil(samples_hint), 4096));
  }
  if (opt.window < 16 || (opt.window & (opt.window - 1)) != 0 || opt.window > (std::size_t{1} << 30))
    throw UsageError(Field::window,
                     std::to_string(opt.window) + " is not a power of two from 16 to 2^30 (e.g. 64, 4096 or 1048576)");
  return opt.window;
}

std::size_t parse_memory_size(const std::string& text) {
  const auto bad = [&] {
    return UsageError(Field::memory, "'" + text +
                                         "' is not a size: give a number of bytes with an optional k, M, G or T "
                                         "(powers of 1024), e.g. 2G or 512M");
  };
  if (text.empty()) throw bad();
  std::size_t pos = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &pos);
  } catch (const std::exception&) {
    throw bad();
  }
  double unit = 1.0;
  if (pos < text.size()) {
    switch (std::toupper(static_cast<unsigned char>(text[pos]))) {
      case 'K': unit = 1024.0; break;
      case 'M': unit = 1024.0 * 1024.0; break;
      case 'G': unit = 1024.0 * 1024.0 * 1024.0; break;
      case 'T': unit = 1024.0 * 1024.0 * 1024.0 * 1024.0; break;
      default: throw bad();
    }
    ++pos;
    if (pos < text.size() && (text[pos] == 'B' || text[pos] == 'b')) ++pos;
  }
  if (pos != text.size() || !(v > 0.0) || !std::isfinite(v) || v * unit < 1024.0 * 1024.0 || v * unit > 1e18)
    throw UsageError(Field::memory, "'" + text + "' is not a usable size: give at least 1M, e.g. 2G or 512M");
  return static_cast<std::size_t>(v * unit);
}

std::size_t memory_budget(const MemoryOptions& opt) {
  if (!opt.memory.empty()) return parse_memory_size(opt.memory);
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return std::size_t{2} << 30;
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) / 2;
}

std::size_t estimated_samples(const std::string& file, const io::SeriesOptions& opt) {
  if (io::looks_like_recording(file)) {
    try {
      std::size_t samples = 0;
      for (const auto& seg : io::read_manifest(file).segments) samples += seg.samples;
      return samples;
    } catch (const std::exception&) {
      return 0;
    }
  }
  const std::size_t bytes = file_size_or_zero(file);
  if (bytes == 0) return 0;
  if (!opt.binary.channels.empty()) {
    const std::size_t frame = opt.binary.frame_bytes();
    return frame > 0 && bytes > opt.binary.header_bytes ? (bytes - opt.binary.header_bytes) / frame : 0;
  }
  // Text (a gzip file's inflated text): from the lines of its first MiB.
  const io::InputEstimate e = io::estimate_input(file);
  if (e.npy_values > 0) return e.npy_rows;
  const auto lines = static_cast<std::size_t>(std::count(e.head.begin(), e.head.end(), '\n'));
  if (lines == 0) return 0;
  // A container (bag, MCAP, .db3, HDF5): its lines say nothing of its samples.
  if (std::find(e.head.begin(), e.head.end(), '\0') != e.head.end()) return 0;
  const double per_line = static_cast<double>(e.head.size()) / static_cast<double>(lines);
  return static_cast<std::size_t>(1.25 * static_cast<double>(e.content_bytes) / per_line) + 1;
}

std::size_t in_memory_bytes(const std::string& file, const io::SeriesOptions& opt) {
  // A robot log: the file and its messages decompressed (a bag directory's size is its files').
  if (opt.binary.channels.empty())
    if (const std::size_t log = io::message_log_bytes(file); log > 0) return log;
  const std::size_t bytes = file_size_or_zero(file);
  if (bytes == 0) return 0;
  if (!opt.binary.channels.empty()) {
    // The mapped file plus 8 bytes per value.
    const std::size_t frame = opt.binary.frame_bytes();
    return bytes + (frame > 0 ? bytes / frame * opt.binary.channels.size() * 8 : 0);
  }
  // A NumPy .npy: the mapped file (inflated, if gzip) plus 8 bytes per value.
  const io::InputEstimate e = io::estimate_input(file);
  if (e.content_bytes == 0) return bytes;  // a recording directory: its chunks' size
  if (e.npy_values > 0) return e.content_bytes + e.npy_values * 8;
  // Text: the parsed doubles, 8 bytes for a number of about 10 characters
  // ("0.0123456,"), and the phase records beside them, about 1.2x the
  // doubles (bench/memory.sh); the pages of the text are dropped behind the
  // parse. Rounded up to the text's size, or to 8 bytes per field when the
  // fields are shorter ("0\n": 4x the text). A gzip file's text (its
  // inflated size, not its compressed size) is held in memory besides.
  const auto fields = static_cast<std::size_t>(std::count_if(
      e.head.begin(), e.head.end(), [](char c) { return c == '\n' || c == ',' || c == ';' || c == '\t'; }));
  const double per_byte = e.head.empty() ? 0.0 : static_cast<double>(fields) / static_cast<double>(e.head.size());
  const auto doubles = static_cast<std::size_t>(8.0 * per_byte * static_cast<double>(e.content_bytes));
  return std::max(e.content_bytes, doubles) + (e.gzip ? e.content_bytes : 0);
}

std::string recording_beyond_budget(const std::string& file, std::size_t need, std::size_t budget) {
  if (need <= budget) return {};
  std::ifstream in(file, std::ios::binary);
  char head[16] = {};
  if (in.read(head, sizeof head) && io::looks_like_ulog(std::string_view(head, sizeof head)))
    return fmt::format(
        "cubecal: warning: reading {} whole would take about {:.0f} MB, more than the memory budget "
        "({:.0f} MB, --memory), and a PX4 ULog file is read whole, not streamed\n",
        file, static_cast<double>(need) / 1e6, static_cast<double>(budget) / 1e6);
  if (!io::looks_like_recording(file)) return {};
  return fmt::format(
      "cubecal: warning: reading {} whole would take about {:.0f} MB, more than the memory budget "
      "({:.0f} MB, --memory), and a recording directory is read whole unless --stream is given "
      "(which streams one segment)\n",
      file, static_cast<double>(need) / 1e6, static_cast<double>(budget) / 1e6);
}

}  // namespace cubecal::cli
