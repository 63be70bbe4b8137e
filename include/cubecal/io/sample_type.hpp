/// @file
/// The type of one binary sample: signed or unsigned integer or IEEE float,
/// its width and byte order, as raw logs and NumPy arrays store them.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace cubecal::io {

/// The kind of a binary sample: signed or unsigned integer, or IEEE floating point.
enum class SampleKind { signed_int, unsigned_int, floating };

/// The type of one binary sample: kind, size and byte order.
struct SampleType {
  /// Integer or floating point.
  SampleKind kind = SampleKind::floating;
  std::size_t bytes = 8;    ///< 1, 2, 4 or 8 (floating: 4 or 8)
  bool big_endian = false;  ///< irrelevant for one byte
  /// Equal kind, size and byte order.
  bool operator==(const SampleType&) const = default;
};

/// "int16le", "uint8", "float32be"...: int8/uint8 (no byte order needed),
/// int16/uint16/int32/uint32/int64/uint64/float32/float64 followed by le or
/// be. nullopt for anything else.
std::optional<SampleType> parse_sample_type(std::string_view name);

/// The name parse_sample_type reads ("int16le").
std::string sample_type_name(const SampleType& t);

/// The sample at `p` (t.bytes bytes) as a double (64-bit integers beyond
/// 2^53 are rounded).
double decode_sample(const SampleType& t, const char* p) noexcept;

}  // namespace cubecal::io
