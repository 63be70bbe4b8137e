// --memory SIZE and --stream: how much memory a run may take, and whether a
// record is read whole or streamed (dev, analyze).
#pragma once
#include <cstddef>
#include <string>

#include <CLI/CLI.hpp>

#include "cubecal/io/series.hpp"

namespace cubecal::cli {

struct MemoryOptions {
  bool stream = false;
  std::string memory;      // "2G", "512M", "300000k", bytes; empty: half the physical memory
  std::size_t window = 0;  // the stream's window bound (a power of two >= 16); 0: from the budget
};

void add_memory_options(CLI::App& cmd, MemoryOptions& opt);

// "2G" -> 2^31 (k, M, G, T: powers of 1024; a plain number is bytes);
// throws UsageError(Field::memory).
std::size_t parse_memory_size(const std::string& text);

// The stream's window bound: --window, or the largest the budget allows
// for `channels` channels, but no larger than the power of two at or above
// `samples_hint` (an estimate of the record's length, 0: unknown): every
// factor of a shorter record is exact with it. UsageError(Field::window) if
// --window is not a power of two of at least 16.
std::size_t stream_window(const MemoryOptions& opt, std::size_t budget, std::size_t channels,
                          std::size_t samples_hint = 0);

// About the samples of `file` (raw frames, .npy: exactly; text, inflated gzip text: from the lines in
// its first MiB, a quarter more for a margin); 0 when unknown (a pipe).
std::size_t estimated_samples(const std::string& file, const io::SeriesOptions& opt);

// The budget: --memory, or half the physical memory (sysconf).
std::size_t memory_budget(const MemoryOptions& opt);

// The bytes reading `file` whole would take (the mapped text or binary plus
// the parsed doubles; a gzip file by its inflated size, a robot log by its
// messages decompressed); 0 when unknown (a pipe, the standard input).
std::size_t in_memory_bytes(const std::string& file, const io::SeriesOptions& opt);

// A recording directory (cubecal record) that needs more than the budget is
// read whole, not switched to the streamed path (which takes only one
// closed segment), and so is a PX4 ULog file (not streamed): the warning
// line to print then, else "".
std::string recording_beyond_budget(const std::string& file, std::size_t need, std::size_t budget);

}  // namespace cubecal::cli
