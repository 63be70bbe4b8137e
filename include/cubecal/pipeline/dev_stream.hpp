/// @file
/// `cubecal dev --stream`: the deviations of every channel of a record read
/// in pieces (io::SampleStream), in one pass and in memory bounded by the
/// window bound (stats/streaming_deviation.hpp), whatever the record's length.
#pragma once
#include <cstddef>

#include "cubecal/io/sample_stream.hpp"
#include "cubecal/pipeline/dev_pipeline.hpp"

namespace cubecal::pipeline {

/// The largest window bound (a power of two, 2^12 .. 2^16) whose accumulators
/// for `channels` channels fit in a quarter of `memory_bytes` (the rest for
/// the reader's pieces and the program); 2^12 when even that does not fit.
/// 2^16 at most: a stream is for records larger than memory, and a larger
/// bound (every factor up to 2^15 exact) costs about 16 bytes per sample of
/// a shorter record, twice its doubles; --window asks for more.
std::size_t window_bound_for(std::size_t memory_bytes, std::size_t channels);

/// Throws UsageError for what a stream cannot compute: a statistic other than
/// adev/oadev/hdev/ohdev (mdev, tdev and totdev need the whole record), phase
/// data, the `all` grid; and as run_dev when no factor fits the record.
/// request.progress, when set, is called after every piece with the
/// fraction of the input read (0 when its size is not known, a pipe: the
/// caller may count input.rows_read() itself).
DevResult run_dev_stream(io::SampleStream& input, const DevRequest& request, std::size_t window_bound);

/// The statistics a stream computes, for the refusal before any reading.
void check_streamable(const DevRequest& request);

}  // namespace cubecal::pipeline
