#include "frame_encoder.hpp"

#include <bit>
#include <cmath>
#include <cstdint>

#include "cubecal/error.hpp"

namespace cubecal::cli {

namespace {

void store(std::string& out, std::uint64_t v, std::size_t n, bool big_endian) {
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t shift = 8 * (big_endian ? n - 1 - i : i);
    out += static_cast<char>((v >> shift) & 0xff);
  }
}

const char* type_name(acquire::FieldType t) {
  using acquire::FieldType;
  switch (t) {
    case FieldType::u8: return "u8";
    case FieldType::i8: return "i8";
    case FieldType::u16: return "u16";
    case FieldType::i16: return "i16";
    case FieldType::u32: return "u32";
    case FieldType::i32: return "i32";
    case FieldType::u64: return "u64";
    case FieldType::i64: return "i64";
    case FieldType::f32: return "f32";
    case FieldType::f64: return "f64";
  }
  return "?";
}

}  // namespace

FrameEncoder::FrameEncoder(acquire::FrameSpec spec, const std::vector<std::string>& columns) : spec_(std::move(spec)) {
  for (const auto& f : spec_.fields) {
    std::size_t c = 0;
    while (c < columns.size() && columns[c] != f.name) ++c;
    if (c == columns.size()) {
      std::string known;
      for (const auto& n : columns) known += (known.empty() ? "" : ", ") + n;
      throw UsageError(Field::frame, "field '" + f.name + "' is not a column of the simulation (" + known + ")");
    }
    column_of_field_.push_back(c);
  }
}

void FrameEncoder::encode(std::span<const double> values, std::string& out) const {
  using acquire::FieldType;
  out += spec_.sync;
  const std::size_t payload = out.size();
  for (std::size_t i = 0; i < spec_.fields.size(); ++i) {
    const auto& f = spec_.fields[i];
    const double v = values[column_of_field_[i]];
    const std::size_t n = acquire::size_of(f.type);
    if (f.type == FieldType::f64) {
      store(out, std::bit_cast<std::uint64_t>(v), n, spec_.big_endian);
      continue;
    }
    if (f.type == FieldType::f32) {
      store(out, std::bit_cast<std::uint32_t>(static_cast<float>(v)), n, spec_.big_endian);
      continue;
    }
    const bool is_signed =
        f.type == FieldType::i8 || f.type == FieldType::i16 || f.type == FieldType::i32 || f.type == FieldType::i64;
    const double r = std::round(v);
    const double bits = static_cast<double>(8 * n);
    const double lo = is_signed ? -std::ldexp(1.0, static_cast<int>(bits) - 1) : 0.0;
    const double hi = is_signed ? std::ldexp(1.0, static_cast<int>(bits) - 1) : std::ldexp(1.0, static_cast<int>(bits));
    if (!(r >= lo && r < hi))
      throw UsageError(Field::frame, "value " + std::to_string(v) + " of field '" + f.name + "' does not fit " +
                                         type_name(f.type) +
                                         ": use a wider type, or f32/f64 for values in physical units");
    const std::uint64_t raw =
        is_signed ? static_cast<std::uint64_t>(static_cast<std::int64_t>(r)) : static_cast<std::uint64_t>(r);
    store(out, raw, n, spec_.big_endian);
  }
  if (spec_.checksum != acquire::Checksum::none) {
    const std::string_view covered(out.data() + payload, out.size() - payload);
    store(out, acquire::checksum_of(spec_.checksum, covered), acquire::size_of(spec_.checksum), spec_.big_endian);
  }
}

}  // namespace cubecal::cli
