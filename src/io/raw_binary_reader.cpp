#include "cubecal/io/raw_binary_reader.hpp"

#include "cubecal/error.hpp"
#include "detail/binary_table.hpp"

namespace cubecal::io {

std::size_t RawLayout::frame_bytes() const noexcept {
  std::size_t n = 0;
  for (const SampleType& t : channels) n += t.bytes;
  return n;
}

RawLayout parse_raw_layout(const std::string& types, std::size_t header_bytes) {
  RawLayout layout;
  layout.header_bytes = header_bytes;
  std::size_t start = 0;
  while (start <= types.size()) {
    const std::size_t comma = types.find(',', start);
    const std::string name = types.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const auto type = parse_sample_type(name);
    if (!type) {
      throw UsageError(Field::binary, "unknown sample type '" + name +
                                          "': use int8, uint8, int16, uint16, int32, uint32, int64, uint64, float32 or "
                                          "float64, with le or be (byte order) after all but the 8-bit types, one per "
                                          "channel separated by commas (e.g. int16le,int16le,float32le)");
    }
    layout.channels.push_back(*type);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return layout;
}

Table read_raw_binary(std::string_view bytes, const std::string& file, const RawLayout& layout, bool missing_as_nan) {
  const std::size_t frame = layout.frame_bytes();
  const std::string types_hint =
      "the frame of " + std::to_string(layout.channels.size()) + " channels is " + std::to_string(frame) + " bytes";
  if (layout.header_bytes > bytes.size()) {
    throw InputError(file, 0, 0,
                     "the file has " + std::to_string(bytes.size()) + " bytes, fewer than the " +
                         std::to_string(layout.header_bytes) + " header bytes to skip",
                     "check {header_bytes}");
  }
  const std::size_t body = bytes.size() - layout.header_bytes;
  const std::size_t rows = body / frame;
  if (const std::size_t rest = body % frame; rest != 0) {
    throw InputError(file, 0, 0,
                     "trailing partial frame: " + std::to_string(rest) + " bytes at byte offset " +
                         std::to_string(layout.header_bytes + rows * frame) + " after " + std::to_string(rows) +
                         " whole frames",
                     types_hint + "; check {binary} and {header_bytes}, or cut the file to whole frames");
  }
  detail::BinaryLayout bl;
  bl.rows = rows;
  bl.row_stride = frame;
  bl.types = layout.channels;
  std::size_t offset = layout.header_bytes;
  for (const SampleType& t : layout.channels) {
    bl.column_offsets.push_back(offset);
    offset += t.bytes;
  }
  return detail::binary_table(bytes, file, bl, missing_as_nan);
}

}  // namespace cubecal::io
