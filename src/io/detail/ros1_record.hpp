// The record layer of a ROS 1 bag: header_len, header fields
// (field_len, "name=value"), data_len, data; all lengths little-endian
// uint32 and checked against the bytes there are. Used by ros1_bag.cpp only.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include "cubecal/error.hpp"

namespace cubecal::io::detail {

// Where a problem sits: the file, and how a position inside the bytes being
// read maps to a byte offset of the file (base + position), or, inside a
// decompressed chunk, to the chunk's offset (said in the message).
struct BagPlace {
  const std::string* file = nullptr;
  std::size_t base = 0;  // file offset of bytes[0] (uncompressed data)
  std::string within;    // e.g. " in the bz2 chunk at byte 4117": positions are not file offsets
  // What to do about it; null: the ROS 1 bag's advice.
  const char* repair = nullptr;
};

[[noreturn]] inline void bag_error(const BagPlace& at, std::size_t pos, const std::string& what) {
  throw InputError(*at.file, 0, 0, "byte " + std::to_string(at.base + pos) + at.within + ": " + what,
                   at.repair != nullptr
                       ? at.repair
                       : "the bag is truncated or corrupt: copy it again, or repair it with `rosbag reindex`");
}

inline std::uint32_t le32(const char* p) noexcept {
  const auto* u = reinterpret_cast<const unsigned char*>(p);
  return static_cast<std::uint32_t>(u[0]) | static_cast<std::uint32_t>(u[1]) << 8 |
         static_cast<std::uint32_t>(u[2]) << 16 | static_cast<std::uint32_t>(u[3]) << 24;
}

struct BagRecord {
  std::size_t offset = 0;   // position of the record in the bytes read
  std::string_view header;  // the header fields
  std::string_view data;
  std::size_t data_offset = 0;  // position of data in the bytes read
  // The value of header field `name`, or nullopt.
  std::optional<std::string_view> field(std::string_view name) const;
};

// Splits "field_len name=value" fields; calls f(name, value) for each.
// Throws (bag_error at `base_pos` + position) on a length that runs past
// the end or a field without '='.
template <class F>
void for_each_field(std::string_view fields, const BagPlace& at, std::size_t base_pos, F&& f) {
  std::size_t p = 0;
  while (p < fields.size()) {
    if (fields.size() - p < 4) bag_error(at, base_pos + p, "header field length cut short");
    const std::uint32_t len = le32(fields.data() + p);
    if (len > fields.size() - p - 4)
      bag_error(at, base_pos + p,
                "header field of " + std::to_string(len) + " bytes runs past its header (" +
                    std::to_string(fields.size() - p - 4) + " bytes left)");
    const std::string_view field = fields.substr(p + 4, len);
    const std::size_t eq = field.find('=');
    if (eq == std::string_view::npos) bag_error(at, base_pos + p, "header field without '='");
    f(field.substr(0, eq), field.substr(eq + 1));
    p += 4 + len;
  }
}

inline std::optional<std::string_view> BagRecord::field(std::string_view name) const {
  // Fields were validated when the record was read (read_record).
  std::size_t p = 0;
  while (p + 4 <= header.size()) {
    const std::uint32_t len = le32(header.data() + p);
    const std::string_view f = header.substr(p + 4, len);
    const std::size_t eq = f.find('=');
    if (f.substr(0, eq) == name) return f.substr(eq + 1);
    p += 4 + len;
  }
  return std::nullopt;
}

// The record at `pos` of `bytes`; advances pos past it.
inline BagRecord read_record(std::string_view bytes, std::size_t& pos, const BagPlace& at) {
  BagRecord r;
  r.offset = pos;
  const std::size_t left = bytes.size() - pos;
  if (left < 4)
    bag_error(at, pos, "record cut short: " + std::to_string(left) + " bytes where a record header length is");
  const std::uint32_t hlen = le32(bytes.data() + pos);
  if (hlen > left - 4)
    bag_error(at, pos,
              "record header of " + std::to_string(hlen) + " bytes runs past the end (" + std::to_string(left - 4) +
                  " bytes left)");
  r.header = bytes.substr(pos + 4, hlen);
  for_each_field(r.header, at, pos + 4, [](std::string_view, std::string_view) {});
  const std::size_t dpos = pos + 4 + hlen;
  if (bytes.size() - dpos < 4) bag_error(at, dpos, "record cut short where its data length is");
  const std::uint32_t dlen = le32(bytes.data() + dpos);
  if (dlen > bytes.size() - dpos - 4)
    bag_error(at, dpos,
              "record data of " + std::to_string(dlen) + " bytes runs past the end (" +
                  std::to_string(bytes.size() - dpos - 4) + " bytes left)");
  r.data = bytes.substr(dpos + 4, dlen);
  r.data_offset = dpos + 4;
  pos = dpos + 4 + dlen;
  return r;
}

// A header field that must be there and hold `size` bytes (size 0: any).
inline std::string_view required_field(const BagRecord& r, std::string_view name, std::size_t size, const BagPlace& at,
                                       const char* record_kind) {
  const auto v = r.field(name);
  if (!v) bag_error(at, r.offset, std::string(record_kind) + " record without its '" + std::string(name) + "' field");
  if (size != 0 && v->size() != size)
    bag_error(at, r.offset,
              std::string(record_kind) + " record's '" + std::string(name) + "' field has " +
                  std::to_string(v->size()) + " bytes, not " + std::to_string(size));
  return *v;
}

}  // namespace cubecal::io::detail
