// Samples as fixed binary frames (`simulate --realtime --frame SPEC`), the
// inverse of acquire::FrameDecoder: the sync bytes, each field of the spec
// taken from the sample's column of the same name ("t", the time in
// seconds, or a channel) in the field's type and byte order, then the
// checksum over the fields. Integer fields hold the value rounded to the
// nearest integer (a model in counts; f32/f64 fields for physical units).
#pragma once
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "cubecal/acquire/frame_spec.hpp"

namespace cubecal::cli {

class FrameEncoder {
 public:
  // `columns`: the names of the values given to encode() in order. A field
  // naming no column is a UsageError(Field::frame) listing them.
  FrameEncoder(acquire::FrameSpec spec, const std::vector<std::string>& columns);
  // Appends the frame of `values` to `out`. A value that does not fit its
  // integer field (or is not finite) is a UsageError(Field::frame) naming it.
  void encode(std::span<const double> values, std::string& out) const;

 private:
  acquire::FrameSpec spec_;
  std::vector<std::size_t> column_of_field_;
};

}  // namespace cubecal::cli
