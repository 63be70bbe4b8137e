// NumPy .npy arrays (format versions 1.0, 2.0 and 3.0): a 1-D array is one
// channel, a 2-D array has a row per sample and a column per channel (C or
// Fortran order). Integer and floating types of either byte order; no time
// axis, so the rate is given (or a column named as time by index).
#pragma once
#include <string>
#include <string_view>

#include "cubecal/io/delimited_reader.hpp"

namespace cubecal::io {

// Whether `bytes` start with the .npy magic "\x93NUMPY".
bool is_npy(std::string_view bytes) noexcept;

// Every column (col1..colN, Table::binary). An unsupported type or shape, a
// damaged header or data that do not match the shape is an InputError
// naming the byte offset; so is an infinite sample, and a NaN unless
// `missing_as_nan` (`--gaps skip`: a NaN is a missing sample, kept as NaN).
Table read_npy(std::string_view bytes, const std::string& file, bool missing_as_nan = false);

}  // namespace cubecal::io
