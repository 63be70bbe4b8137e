#include "cubecal/io/sample_type.hpp"

#include <bit>
#include <cstdint>
#include <cstring>

namespace cubecal::io {

std::optional<SampleType> parse_sample_type(std::string_view name) {
  struct Base {
    std::string_view name;
    SampleKind kind;
    std::size_t bytes;
  };
  static constexpr Base kBases[] = {
      {"int8", SampleKind::signed_int, 1},  {"uint8", SampleKind::unsigned_int, 1},
      {"int16", SampleKind::signed_int, 2}, {"uint16", SampleKind::unsigned_int, 2},
      {"int32", SampleKind::signed_int, 4}, {"uint32", SampleKind::unsigned_int, 4},
      {"int64", SampleKind::signed_int, 8}, {"uint64", SampleKind::unsigned_int, 8},
      {"float32", SampleKind::floating, 4}, {"float64", SampleKind::floating, 8},
  };
  for (const Base& b : kBases) {
    if (name.substr(0, b.name.size()) != b.name) continue;
    const std::string_view order = name.substr(b.name.size());
    if (order.empty() && b.bytes == 1) return SampleType{b.kind, 1, false};
    if (order == "le") return SampleType{b.kind, b.bytes, false};
    if (order == "be") return SampleType{b.kind, b.bytes, true};
  }
  return std::nullopt;
}

std::string sample_type_name(const SampleType& t) {
  std::string s = t.kind == SampleKind::floating ? "float" : t.kind == SampleKind::signed_int ? "int" : "uint";
  s += std::to_string(8 * t.bytes);
  if (t.bytes > 1) s += t.big_endian ? "be" : "le";
  return s;
}

double decode_sample(const SampleType& t, const char* p) noexcept {
  std::uint64_t u = 0;
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  if (t.big_endian) {
    for (std::size_t i = 0; i < t.bytes; ++i) u = (u << 8) | b[i];
  } else {
    for (std::size_t i = t.bytes; i-- > 0;) u = (u << 8) | b[i];
  }
  const unsigned shift = static_cast<unsigned>(64 - 8 * t.bytes);
  switch (t.kind) {
    case SampleKind::unsigned_int: return static_cast<double>(u);
    case SampleKind::signed_int:
      // Sign-extend by shifting the value to the top and back.
      return static_cast<double>(static_cast<std::int64_t>(u << shift) >> shift);
    case SampleKind::floating:
      if (t.bytes == 4) return static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(u)));
      return std::bit_cast<double>(u);
  }
  return 0.0;
}

}  // namespace cubecal::io
