#include "binary_table.hpp"

#include <cmath>
#include <limits>

#include "cubecal/error.hpp"

namespace cubecal::io::detail {

Table binary_table(std::string_view bytes, const std::string& file, const BinaryLayout& layout, bool missing_as_nan) {
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
      const bool nan = std::isnan(out[r]);
      if (nan && missing_as_nan) {
        out[r] = std::numeric_limits<double>::quiet_NaN();  // whatever its payload or sign
        continue;
      }
      const std::size_t offset = layout.column_offsets[c] + r * layout.row_stride;
      throw InputError(file, 0, 0,
                       std::string(nan ? "NaN" : "infinite value") + " at byte offset " + std::to_string(offset) +
                           " (row " + std::to_string(r + 1) + ", column " + std::to_string(c + 1) + ")",
                       nan ? kNanSampleHint : "an invalid sample, never a missing one: cut the record there");
    }
  }
  for (std::size_t c = 0; c < t.total_columns; ++c) {
    t.indices.push_back(c);
    t.names.push_back("col" + std::to_string(c + 1));
  }
  return t;
}

}  // namespace cubecal::io::detail
