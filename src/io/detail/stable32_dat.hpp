// Stable32's own data files (.DAT as Stable32 writes them): a header of
// "Name: value" lines (File, Date, Type, Points, Tau, Addend, Multiplier,
// Tag Scale, Tag Offset) closed by "# Header End", then one value per line.
// The header says the data type, the sampling interval and the scaling the
// values take (value * Multiplier + Addend, Stable32's Scale function).
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "cubecal/stats/statistic.hpp"

namespace cubecal::io::detail {

// What a Stable32 header says.
struct Stable32Header {
  std::size_t lines = 0;              // physical lines up to and including "# Header End"
  std::optional<DataType> type;       // "Type: Phase" or "Type: Frequency"
  std::optional<double> tau;          // "Tau:", seconds
  std::optional<std::size_t> points;  // "Points:"
  double addend = 0.0;                // "Addend:"
  double multiplier = 1.0;            // "Multiplier:"
};

// The header when `text` starts with one (its first line "File:"), none
// otherwise. A header line that cannot be read (an unknown type, a Tau that
// is not a positive number, a Multiplier of 0, a line that is not
// "Name: value") or a header without "# Header End" is an InputError at its
// line.
std::optional<Stable32Header> stable32_header(std::string_view text, const std::string& file);

}  // namespace cubecal::io::detail
