#include "binary_table.hpp"

#include <cmath>

#include "cubecal/error.hpp"

namespace cubecal::io::detail {

Table binary_table(std::string_view bytes, const std::string& file, const BinaryLayout& layout) {
  Table t;
  t.file = file;
  t.binary = true;
  t.has_header = false;
  t.total_columns = layout.types.size();
  t.bytes = bytes.size();
  t.first_data_line = 0;
  t.data.resize(t.total_columns);
  for (std::size_t c = 0; c < t.total_columns; ++c) {
    const SampleType type = layout.types[c];
    std::vector<double>& out = t.data[c];
    out.resize(layout.rows);
    if (layout.rows == 0) continue;  // (the bytes may be empty, their data() null)
    const char* p = bytes.data() + layout.column_offsets[c];
    for (std::size_t r = 0; r < layout.rows; ++r, p += layout.row_stride) out[r] = decode_sample(type, p);
    if (type.kind != SampleKind::floating) continue;
    for (std::size_t r = 0; r < layout.rows; ++r) {
      if (std::isfinite(out[r])) continue;
      const std::size_t offset = layout.column_offsets[c] + r * layout.row_stride;
      throw InputError(file, 0, 0,
                       std::string(std::isnan(out[r]) ? "NaN" : "infinite value") + " at byte offset " +
                           std::to_string(offset) + " (row " + std::to_string(r + 1) + ", column " +
                           std::to_string(c + 1) + ")",
                       "a missing or invalid sample: cut the record there, or fill the gap");
    }
  }
  for (std::size_t c = 0; c < t.total_columns; ++c) {
    t.indices.push_back(c);
    t.names.push_back("col" + std::to_string(c + 1));
  }
  return t;
}

}  // namespace cubecal::io::detail
