// A binary record as a table of every column: where each sample of each
// column sits in the bytes and of which type. Shared by the NumPy and raw
// readers, which differ only in how they learn the layout.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/io/delimited_reader.hpp"
#include "cubecal/io/sample_type.hpp"

namespace cubecal::io::detail {

struct BinaryLayout {
  std::size_t rows = 0;
  // Sample (row r, column c) starts at column_offsets[c] + r * row_stride.
  std::size_t row_stride = 0;
  std::vector<std::size_t> column_offsets;
  std::vector<SampleType> types;  // one per column
};

// Every column decoded, named col1..colN (Table::binary set, no header). An
// infinite value is an InputError naming its byte offset, row and column; so
// is a NaN, unless `missing_as_nan` (`--gaps skip`: a NaN is a missing
// sample, kept as NaN). The layout must lie within `bytes` (the readers
// check it).
Table binary_table(std::string_view bytes, const std::string& file, const BinaryLayout& layout,
                   bool missing_as_nan = false);

// The hint of the error for a NaN sample of a binary record read without
// `--gaps skip`.
inline constexpr const char* kNanSampleHint =
    "a missing sample: {gaps} skip leaves it out of the OADEV terms (dev, davar); otherwise cut the record "
    "there or fill the gap";

}  // namespace cubecal::io::detail
