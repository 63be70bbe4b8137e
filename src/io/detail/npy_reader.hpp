// NumPy .npy arrays (format versions 1.0, 2.0 and 3.0): a 1-D array is one
// channel, a 2-D array has a row per sample and a column per channel (C or
// Fortran order). Integer and floating types of either byte order; no time
// axis, so the rate is given (or a column named as time by index).
#pragma once
#include <string>
#include <string_view>

#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/io/sample_type.hpp"

namespace cubecal::io {

// Whether `bytes` start with the .npy magic "\x93NUMPY".
bool is_npy(std::string_view bytes) noexcept;

// What the header of a .npy says.
struct NpyHeader {
  SampleType type;
  std::string descr;  // as written ('<f8')
  std::string shape;  // as a Python tuple ("(200, 3)")
  std::size_t rows = 0, cols = 0;
  std::size_t data_at = 0;     // byte offset of the data
  bool fortran_order = false;  // a 2-D array stored column after column
  std::size_t data_bytes() const noexcept { return rows * cols * type.bytes; }
};

// Where the data start, from the preamble (the first 12 bytes, or all of a
// shorter file); InputError as read_npy.
std::size_t npy_data_offset(std::string_view bytes, const std::string& file);
// The header, from bytes that hold at least npy_data_offset() bytes (or all
// of a shorter file); InputError as read_npy for an unsupported type or
// shape or a damaged header.
NpyHeader read_npy_header(std::string_view bytes, const std::string& file);
// The problem and hint of data shorter or longer than the header declares
// (`have` bytes of data; `extra` bytes after them).
std::string npy_short_data(const NpyHeader& h, std::size_t have);
std::string npy_extra_data(const NpyHeader& h, std::size_t extra);
inline constexpr const char* kNpyShortHint = "the file is incomplete; copy it again, or save it again";
inline constexpr const char* kNpyExtraHint =
    "the file is damaged or not one array (numpy.savez writes a .npz archive); save it again with numpy.save";

// Every column (col1..colN, Table::binary). An unsupported type or shape, a
// damaged header or data that do not match the shape is an InputError
// naming the byte offset; so is an infinite sample, and a NaN unless
// `missing_as_nan` (`--gaps skip`: a NaN is a missing sample, kept as NaN).
Table read_npy(std::string_view bytes, const std::string& file, bool missing_as_nan = false);

}  // namespace cubecal::io
