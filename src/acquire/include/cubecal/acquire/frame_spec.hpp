// A fixed binary frame, as `--frame` gives it:
//   sync=A55A;fields=t:u32,gx:i16,gy:i16,gz:i16;checksum=xor8;endian=le
// sync: 1-4 bytes in hex; fields: name:type, type one of u8 i8 u16 i16 u32
// i32 u64 i64 f32 f64; checksum: none, xor8, sum8, crc16 (CCITT-FALSE) or
// crc32 (zlib), over the bytes after the sync up to the checksum, which
// follows the fields; endian: le (the default) or be, for the fields and
// the checksum.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace cubecal::acquire {

enum class FieldType { u8, i8, u16, i16, u32, i32, u64, i64, f32, f64 };
enum class Checksum { none, xor8, sum8, crc16, crc32 };

std::size_t size_of(FieldType t) noexcept;
std::size_t size_of(Checksum c) noexcept;

struct FrameField {
  std::string name;
  FieldType type = FieldType::u8;
  std::size_t offset = 0;  // from the frame's first byte (the sync's)
};

struct FrameSpec {
  std::string text;  // as given
  std::string sync;  // the sync bytes
  std::vector<FrameField> fields;
  Checksum checksum = Checksum::none;
  bool big_endian = false;
  std::size_t payload_size() const noexcept;  // the fields' bytes
  std::size_t frame_size() const noexcept;    // sync + fields + checksum
};

// Parses SPEC; a UsageError(Field::frame) says what is wrong and what is allowed.
FrameSpec parse_frame_spec(std::string_view spec);

// The checksum of `bytes` by `c` (0 for none).
std::uint32_t checksum_of(Checksum c, std::string_view bytes) noexcept;

}  // namespace cubecal::acquire
