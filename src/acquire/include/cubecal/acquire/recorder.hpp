// The recording loop: bytes from a source, framed into samples (text lines
// or binary frames), each stamped with the host's receive time (one stamp
// per read() batch), written to chunk files that rotate by time and size;
// malformed input to the segment's rejects file; the device time (when the
// data have one) checked for gaps and resets. The buffers go to the kernel
// every flush interval, and every sync interval (and at rotation and at the
// end) the chunk and the rejects are fsync'd and the manifest replaced
// atomically, so that it never claims more than is on disk.
//
// A directory that already holds a recording gets a new segment; a
// segment its last run left open (a crash) is recovered first. The
// recorder never prints: notices (a segment appended, a chunk recovered) and
// status snapshots go to callbacks.
#pragma once
#include <csignal>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cubecal/acquire/frame_spec.hpp"
#include "cubecal/acquire/line_framer.hpp"
#include "cubecal/acquire/source.hpp"
#include "cubecal/io/recording_manifest.hpp"

namespace cubecal::acquire {

struct RecorderStatus {
  double elapsed_s = 0.0;
  std::size_t samples = 0;  // this segment
  std::size_t rejects = 0;
  std::size_t gaps = 0, resets = 0, reconnects = 0;
  double samples_per_s = 0.0;      // over the last status interval
  double device_rate_hz = 0.0;     // from the device time (0: none or not yet)
  std::vector<std::string> names;  // data columns (empty until the layout is known)
  std::vector<double> last;        // the last sample's values
  std::size_t bytes = 0;           // chunk bytes of this segment
  int segment = 0;
  std::size_t chunk = 0;  // 1-based chunk of the segment being written
};

enum class RecordEnd { source_ended, duration, stopped };

struct RecorderSummary {
  RecorderStatus status;
  RecordEnd end = RecordEnd::source_ended;
  std::string segment_dir;  // DIR/seg-NNN (empty: nothing was received)
  std::size_t chunks = 0;
  std::size_t partial_bytes = 0;
  std::size_t blank_lines = 0;
  // Nothing was recorded but input arrived that was not data (no layout was
  // ever found): how many such pieces, and the first one's reason and bytes
  // (as received), so that they are reported rather than dropped.
  std::size_t unrecorded_rejects = 0;
  std::string first_unrecorded_reason, first_unrecorded_data;
  // The layout was found (a header line, --columns, --frame) though no
  // sample arrived.
  bool layout_known = false;
};

struct RecorderOptions {
  std::string out_dir;
  LineFramerOptions text;          // text framing (when no frame)
  std::optional<FrameSpec> frame;  // binary frames
  std::string time_col;            // name or 1-based index; empty: detected by name
  std::optional<double> rate_hz;
  std::optional<std::string> unit;
  double duration_s = 0.0;  // 0: until the source ends or a stop
  double chunk_seconds = 600.0;
  std::size_t chunk_bytes = std::size_t{64} << 20;
  double flush_interval_s = 0.1;  // buffers to the kernel (what survives kill -9)
  double sync_interval_s = 0.5;   // fsync + manifest (what survives a power loss); at most 1 s
  double status_interval_s = 0.5;
  std::size_t read_buffer = 256 << 10;
  // Set from a signal handler to end the run cleanly.
  const volatile std::sig_atomic_t* stop = nullptr;
  std::function<void(const std::string&)> on_notice;
  std::function<void(const RecorderStatus&)> on_status;
  // Every sample's values (for a live statistic); off when empty.
  std::function<void(std::span<const double>)> on_sample;
};

class Recorder {
 public:
  // Checks DIR (created when missing; an existing recording is recovered
  // and continued; anything else there is refused) before any byte is read.
  Recorder(Source& source, RecorderOptions opt);
  ~Recorder();

  // Records until the source ends, the duration is reached or *stop is set.
  // Throws WriteFailure when the disk refuses data (the manifest then still
  // describes what was synced before), UsageError when the source's layout
  // differs from the recording's.
  RecorderSummary run();

  const io::RecordingManifest& manifest() const noexcept { return manifest_; }

  /// Hands the buffered chunk and rejects to the kernel now (what the run
  /// does every flush interval): every sample recorded so far then survives
  /// a kill -9. For a callback of the run (on_sample) that is about to tell
  /// another process how many samples there are. Throws WriteFailure.
  void flush();

 private:
  class Impl;
  io::RecordingManifest manifest_;  // before impl_, which fills it
  std::unique_ptr<Impl> impl_;
};

// Recovers the segments a crash left open in DIR's manifest (see Recorder);
// returns a notice per recovered chunk. Exposed for tests.
std::vector<std::string> recover_recording(const std::string& dir, io::RecordingManifest& m);

}  // namespace cubecal::acquire
