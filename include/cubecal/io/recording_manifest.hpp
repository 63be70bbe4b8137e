/// @file
/// The manifest of a recording directory (`cubecal record`, format
/// "cubecal-record/1"): the columns and framing shared by every chunk, and per
/// segment (one run of the recorder) its chunks with their sample and byte
/// counts and CRC-32, and the events seen in the device time (gaps, resets)
/// and the source (reconnects). The recorder rewrites it atomically after
/// every fsync of the data, so that it never claims more than is on disk; the
/// recording reader (recording.hpp) reads it to join the segments.
///
///   DIR/manifest.json
///   DIR/seg-001/chunk-000001.csv ...   host_mono_s,host_utc_s,`<columns>`
///   DIR/seg-001/rejects.csv            host_mono_s,host_utc_s,reason,data
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal::io {

/// The manifest's format name and version.
inline constexpr std::string_view kRecordingFormat = "cubecal-record/1";
/// The manifest's file name, in the recording directory.
inline constexpr std::string_view kManifestName = "manifest.json";
/// The file name of a segment's rejected lines or frames.
inline constexpr std::string_view kRejectsName = "rejects.csv";
/// The two columns every chunk starts with, before the data columns.
inline constexpr std::string_view kHostMonoColumn = "host_mono_s";
/// The host's UTC time of a sample (s since the Unix epoch), the second column of every chunk.
inline constexpr std::string_view kHostUtcColumn = "host_utc_s";

/// One chunk file of a recording segment.
struct RecordingChunk {
  std::string file;                    ///< "chunk-000001.csv", in the segment's directory
  std::size_t samples = 0;             ///< data lines (the header line not counted)
  std::size_t bytes = 0;               ///< file size, header included
  std::optional<std::uint32_t> crc32;  ///< zlib crc32 of the whole file; none while open
  double first_host_utc_s = 0.0;       ///< host UTC stamp of the first sample (0 when none yet)
  /// Host UTC stamp of the last sample (s; 0 when none yet).
  double last_host_utc_s = 0.0;
  bool open = false;  ///< still being written (counts of its last flush)
};

/// Something the recorder noticed in the stream. `sample` counts from the
/// segment's first sample (the sample at which it was seen).
struct RecordingEvent {
  /// What was noticed: a gap in the device time, a reset of the device time, the source reconnected.
  enum class Kind { gap, reset, reconnect };
  /// What was noticed.
  Kind kind = Kind::gap;
  /// The sample at which it was seen, from the segment's first.
  std::size_t sample = 0;
  double device_time = 0.0;  ///< gap, reset: the device time of that sample
  double dt = 0.0;           ///< gap: the interval seen
  double expected_dt = 0.0;  ///< gap: the interval expected
  double previous = 0.0;     ///< reset: the device time before it
  double host_utc_s = 0.0;   ///< reconnect: when the source came back
};

/// How a segment ended: still open, closed cleanly, or recovered after a crash.
enum class SegmentEnd { open, clean, recovered };

/// One segment of a recording: one run of the recorder, in its own directory.
struct RecordingSegment {
  int index = 1;              ///< 1-based
  std::string dir;            ///< "seg-001"
  std::string start_utc;      ///< ISO 8601 UTC with nanoseconds, "2026-11-27T13:00:00.123456789Z"
  double start_mono_s = 0.0;  ///< CLOCK_MONOTONIC at the start
  std::string end_utc;        ///< empty while open
  /// How the segment ended.
  SegmentEnd end = SegmentEnd::open;
  /// Samples recorded in the segment.
  std::size_t samples = 0;
  std::size_t rejects = 0;        ///< entries of the segment's rejects.csv
  std::size_t partial_bytes = 0;  ///< bytes of a partial last line (counted, not kept as a sample)
  /// The segment's chunk files, in order.
  std::vector<RecordingChunk> chunks;
  /// What the recorder noticed, in order.
  std::vector<RecordingEvent> events;
};

/// How the source's bytes were cut into samples.
struct RecordingFraming {
  /// Text lines or binary frames.
  enum class Kind { text, binary };
  /// Text lines or binary frames.
  Kind kind = Kind::text;
  std::string delimiter = ",";  ///< text: the delimiter of the source's lines ("," "\t" ";" " ")
  std::string frame;            ///< binary: the --frame spec as given
};

/// The manifest of a recording directory (cubecal record): its columns, source and segments.
struct RecordingManifest {
  /// kRecordingFormat.
  std::string format{kRecordingFormat};
  std::vector<std::string> columns;  ///< data columns, after host_mono_s,host_utc_s
  /// The device's time column among columns, when there is one.
  std::optional<std::string> time_column;
  /// The nominal sampling rate (Hz), when given.
  std::optional<double> rate_hz;
  /// The data's unit, when given.
  std::optional<std::string> unit;
  /// How samples were framed.
  RecordingFraming framing;
  std::string source;  ///< "/dev/ttyUSB0 at 115200 baud", "tcp:host:port", "stdin"
  /// The segments, in order.
  std::vector<RecordingSegment> segments;
};

/// "open", "clean", "recovered". Throws nothing.
std::string_view to_string(SegmentEnd e) noexcept;
/// "gap", "reset", "reconnect". Throws nothing.
std::string_view to_string(RecordingEvent::Kind k) noexcept;
/// "0a1b2c3d"
std::string crc32_hex(std::uint32_t crc);

/// The manifest as JSON text (pretty-printed, ending in a newline).
std::string manifest_text(const RecordingManifest& m);
/// Parses manifest text; `file` names it in errors (InputError: not JSON, not
/// "cubecal-record/1", a field missing or of the wrong type).
RecordingManifest parse_manifest(std::string_view text, const std::string& file);

/// Reads DIR/manifest.json (InputError when unreadable or malformed).
RecordingManifest read_manifest(const std::string& dir);
/// True when `dir` is a directory holding a manifest.json whose "format" is
/// "cubecal-record/1" (any error reading it: false).
bool is_recording_dir(const std::string& dir);

/// replace_file_atomically(DIR/manifest.json, manifest_text(m)).
void write_manifest(const std::string& dir, const RecordingManifest& m);

/// "2026-11-27T13:00:00.123456789Z" from a CLOCK_REALTIME reading.
std::string utc_iso8601(std::int64_t seconds, long nanoseconds);

}  // namespace cubecal::io
