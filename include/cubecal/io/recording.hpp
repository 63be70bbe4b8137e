/// @file
/// A recording directory of `cubecal record` (recording_manifest.hpp) read as
/// a record: the chunks of every segment joined in order, checked against the
/// manifest (a closed chunk's byte count and CRC-32; the open chunk of a
/// running or crashed recorder up to its last complete line), with its time
/// from the device time column, or else from the host receive stamps.
///
/// Time: the device time column (the manifest's time_column, or
/// SeriesOptions::time_col naming any column, host_mono_s and host_utc_s
/// included) times the samples. Without one, a rate (SeriesOptions::rate_hz,
/// else the manifest's rate_hz) spaces the samples of each segment evenly
/// from the segment's first receive stamp; with neither, the receive stamps
/// host_mono_s are the time stamps. Each segment's monotonic stamps are
/// placed by its start_utc, so that the segments follow each other on one
/// clock: a device clock that starts again with a segment (a power cycle)
/// is shifted to where the host clock puts the segment's first sample; one
/// that ran on between the segments (the recorder restarted, the sensor not)
/// is kept; a device clock that goes back inside a segment (the sensor
/// restarted, the recorder ran on) is placed the same way from there. The
/// interval at such a break is then checked like any interval of a record
/// (SeriesOptions::gaps): refused by default, cut there
/// with GapPolicy::split, filled with missing samples with GapPolicy::skip
/// when it is a whole number of periods.
#pragma once
#include <string>
#include <vector>

#include "cubecal/io/series.hpp"

namespace cubecal::io {

/// The whole recording as one record (Series::file is `dir`). Errors name
/// the chunk and line (InputError), e.g. "DIR/seg-001/chunk-000002.csv:
/// CRC-32 ... the chunk changed since it was recorded".
Series read_recording(const std::string& dir, const SeriesOptions& opt);

/// Each segment with samples as a record of its own (Series::file is
/// DIR/seg-NNN): the runs of a power-cycled session, for `turnon`.
std::vector<Series> read_recording_segments(const std::string& dir, const SeriesOptions& opt);

/// Whether `path` is a directory to be read as a recording: it holds a
/// manifest.json and is not a ROS 2 bag (no metadata.yaml). The manifest's
/// format is checked when it is read.
bool looks_like_recording(const std::string& path);

}  // namespace cubecal::io
