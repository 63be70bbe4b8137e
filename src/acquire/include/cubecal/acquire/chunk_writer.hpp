// One chunk file of a recording: a CSV file with its header line
// (host_mono_s,host_utc_s,<columns>) and one line per sample, written
// through a buffer. flush() hands the buffer to the kernel (what survives
// the recorder being killed), sync() also fsyncs it (what survives a power
// loss) and fixes the counts the manifest may then claim; close() syncs and
// gives the chunk's CRC-32. The recovery of a chunk left open by a crash
// is here too.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/io/recording_manifest.hpp"

namespace cubecal::acquire {

namespace detail {
class AppendFile;
}

// "chunk-000001.csv"
std::string chunk_file_name(std::size_t index);
// The chunk's header line, without its line end.
std::string chunk_header(const std::vector<std::string>& columns);

class ChunkWriter {
 public:
  // Creates DIR/FILE (it must not exist) and writes the header line.
  ChunkWriter(const std::string& dir, std::string file, const std::vector<std::string>& columns);
  ~ChunkWriter();

  // One sample: `prefix` is "MONO,UTC," of its batch, `fields` the data.
  void add(std::string_view prefix, std::string_view fields, double host_utc_s);
  void flush();
  void sync();
  io::RecordingChunk close();

  // The chunk as of the last sync() ("open": true): what is surely on disk.
  const io::RecordingChunk& synced() const noexcept { return synced_; }
  std::size_t bytes() const noexcept;  // including what is buffered
  std::size_t samples() const noexcept { return samples_; }
  const std::string& path() const noexcept;

 private:
  std::unique_ptr<detail::AppendFile> file_;
  io::RecordingChunk synced_;
  std::size_t samples_ = 0;
  double first_utc_ = 0.0, last_utc_ = 0.0;
};

// A chunk left open by a crash, made whole: its complete lines are kept
// (a line past the part the manifest vouched for must have the chunk's
// field count and no NUL byte, else it and all after it count as the
// partial tail), the partial tail is cut off the file and returned, and the
// chunk's samples, bytes, CRC-32 and host times are recomputed.
struct RecoveredChunk {
  io::RecordingChunk chunk;  // closed
  std::string tail;          // the bytes cut off (no line end), to go to the rejects
  std::string last_stamps;   // "MONO,UTC," of the last line kept (",," when none)
  bool had_header = true;    // false: not even the header line was complete
};
RecoveredChunk recover_chunk(const std::string& dir, const io::RecordingChunk& as_manifest, std::size_t columns);

}  // namespace cubecal::acquire
