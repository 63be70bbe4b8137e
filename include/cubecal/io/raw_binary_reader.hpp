/// @file
/// Raw interleaved binary: a record of fixed-size frames, one sample of each
/// channel per frame in a declared type (e.g. three int16le gyro axes and a
/// float32le temperature), after an optional header of bytes to skip. There
/// is no time axis: the rate is given.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/io/sample_type.hpp"

namespace cubecal::io {

/// The layout of raw interleaved binary frames: one sample of each channel per frame, after a header.
struct RawLayout {
  std::vector<SampleType> channels;  ///< empty: not raw binary
  std::size_t header_bytes = 0;      ///< skipped at the start
  /// Bytes of one frame: the sum of the channels' sample sizes. Throws nothing.
  std::size_t frame_bytes() const noexcept;
};

/// "int16le,int16le,float32le" (see parse_sample_type); throws
/// UsageError(Field::binary) naming an unknown type.
RawLayout parse_raw_layout(const std::string& types, std::size_t header_bytes);

/// Every channel as a column (col1..colN, Table::binary). A header longer
/// than the file, or a trailing partial frame, is an InputError naming its
/// byte offset; so is an infinite float sample, and a NaN unless
/// `missing_as_nan` (`--gaps skip`: a NaN is a missing sample, kept as NaN).
Table read_raw_binary(std::string_view bytes, const std::string& file, const RawLayout& layout,
                      bool missing_as_nan = false);

}  // namespace cubecal::io
