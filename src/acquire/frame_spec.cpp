// Binary frame specs and checksums (frame_spec.hpp).
#include "cubecal/acquire/frame_spec.hpp"

#include <zlib.h>

#include <set>

#include "cubecal/error.hpp"
#include "cubecal/printable_text.hpp"

namespace cubecal::acquire {

namespace {

[[noreturn]] void bad(const std::string& what) {
  throw UsageError(Field::frame,
                   printable_text(what) +
                       " (e.g. {frame} 'sync=A55A;fields=t:u32,gx:i16,gy:i16,gz:i16;checksum=xor8;endian=le'; "
                       "types u8 i8 u16 i16 u32 i32 u64 i64 f32 f64, checksums none xor8 sum8 crc16 crc32)");
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> out;
  for (;;) {
    const auto at = s.find(sep);
    out.push_back(s.substr(0, at));
    if (at == std::string_view::npos) break;
    s.remove_prefix(at + 1);
  }
  return out;
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

FieldType field_type(std::string_view t) {
  static constexpr std::pair<std::string_view, FieldType> kTypes[] = {
      {"u8", FieldType::u8},   {"i8", FieldType::i8},   {"u16", FieldType::u16}, {"i16", FieldType::i16},
      {"u32", FieldType::u32}, {"i32", FieldType::i32}, {"u64", FieldType::u64}, {"i64", FieldType::i64},
      {"f32", FieldType::f32}, {"f64", FieldType::f64}};
  for (const auto& [name, type] : kTypes)
    if (name == t) return type;
  bad("{frame}: unknown field type '" + std::string(t) + "'");
}

}  // namespace

std::size_t size_of(FieldType t) noexcept {
  switch (t) {
    case FieldType::u8:
    case FieldType::i8: return 1;
    case FieldType::u16:
    case FieldType::i16: return 2;
    case FieldType::u32:
    case FieldType::i32:
    case FieldType::f32: return 4;
    case FieldType::u64:
    case FieldType::i64:
    case FieldType::f64: return 8;
  }
  return 1;
}

std::size_t size_of(Checksum c) noexcept {
  switch (c) {
    case Checksum::none: return 0;
    case Checksum::xor8:
    case Checksum::sum8: return 1;
    case Checksum::crc16: return 2;
    case Checksum::crc32: return 4;
  }
  return 0;
}

std::size_t FrameSpec::payload_size() const noexcept {
  std::size_t n = 0;
  for (const auto& f : fields) n += size_of(f.type);
  return n;
}

std::size_t FrameSpec::frame_size() const noexcept { return sync.size() + payload_size() + size_of(checksum); }

FrameSpec parse_frame_spec(std::string_view spec) {
  FrameSpec s;
  s.text = std::string(spec);
  std::set<std::string, std::less<>> keys;  // those given, each once
  for (const std::string_view item : split(spec, ';')) {
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string_view::npos) bad("{frame}: '" + std::string(item) + "' is not KEY=VALUE");
    const std::string_view key = item.substr(0, eq), value = item.substr(eq + 1);
    // A key given twice would add a second sync to the first, or a second
    // field list to the first, beyond what either says.
    if (!keys.insert(std::string(key)).second)
      bad("{frame}: " + std::string(key) + " is given twice; give each key once");
    if (key == "sync") {
      if (value.size() < 2 || value.size() > 8 || value.size() % 2 != 0)
        bad("{frame}: sync is 1 to 4 bytes in hex, got '" + std::string(value) + "'");
      for (std::size_t i = 0; i < value.size(); i += 2) {
        const int hi = hex_digit(value[i]), lo = hex_digit(value[i + 1]);
        if (hi < 0 || lo < 0) bad("{frame}: sync '" + std::string(value) + "' is not hex");
        s.sync.push_back(static_cast<char>(hi * 16 + lo));
      }
    } else if (key == "fields") {
      std::set<std::string, std::less<>> seen;
      for (const std::string_view f : split(value, ',')) {
        const auto colon = f.find(':');
        if (colon == std::string_view::npos || colon == 0)
          bad("{frame}: field '" + std::string(f) + "' is not NAME:TYPE");
        FrameField field;
        field.name = std::string(f.substr(0, colon));
        field.type = field_type(f.substr(colon + 1));
        if (!seen.insert(field.name).second) bad("{frame}: field '" + field.name + "' is named twice");
        s.fields.push_back(std::move(field));
      }
    } else if (key == "checksum") {
      if (value == "none")
        s.checksum = Checksum::none;
      else if (value == "xor8")
        s.checksum = Checksum::xor8;
      else if (value == "sum8")
        s.checksum = Checksum::sum8;
      else if (value == "crc16")
        s.checksum = Checksum::crc16;
      else if (value == "crc32")
        s.checksum = Checksum::crc32;
      else
        bad("{frame}: unknown checksum '" + std::string(value) + "'");
    } else if (key == "endian") {
      if (value == "le")
        s.big_endian = false;
      else if (value == "be")
        s.big_endian = true;
      else
        bad("{frame}: endian is le or be, got '" + std::string(value) + "'");
    } else {
      bad("{frame}: unknown key '" + std::string(key) + "' (sync, fields, checksum, endian)");
    }
  }
  if (s.sync.empty()) bad("{frame}: sync=HEX is missing");
  if (s.fields.empty()) bad("{frame}: fields=NAME:TYPE,... is missing");
  std::size_t offset = s.sync.size();
  for (auto& f : s.fields) {
    f.offset = offset;
    offset += size_of(f.type);
  }
  return s;
}

std::uint32_t checksum_of(Checksum c, std::string_view bytes) noexcept {
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::size_t n = bytes.size();
  switch (c) {
    case Checksum::none: return 0;
    case Checksum::xor8: {
      unsigned v = 0;
      for (std::size_t i = 0; i < n; ++i) v ^= p[i];
      return v & 0xFFu;
    }
    case Checksum::sum8: {
      unsigned v = 0;
      for (std::size_t i = 0; i < n; ++i) v += p[i];
      return v & 0xFFu;
    }
    case Checksum::crc16: {  // CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection
      std::uint32_t crc = 0xFFFF;
      for (std::size_t i = 0; i < n; ++i) {
        crc ^= static_cast<std::uint32_t>(p[i]) << 8;
        for (int b = 0; b < 8; ++b) crc = (crc & 0x8000u) ? ((crc << 1) ^ 0x1021u) : (crc << 1);
        crc &= 0xFFFFu;
      }
      return crc;
    }
    case Checksum::crc32: return static_cast<std::uint32_t>(::crc32(0L, p, static_cast<uInt>(n)));
  }
  return 0;
}

}  // namespace cubecal::acquire
