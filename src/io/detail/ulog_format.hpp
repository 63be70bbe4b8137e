// ULog format definitions: the text of an 'F' message
// ("name:type field;type[n] field;...") split into fields, and the layout
// (offsets and sizes, nested types resolved) of every format once all are
// known. Used by ulog.cpp only.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "cubecal/io/ulog.hpp"

namespace cubecal::io::detail {

// The bytes of a basic ULog type (int8_t ... double, bool, char); 0 for
// any other name (a nested format, or unknown).
std::size_t ulog_basic_size(std::string_view type) noexcept;

// The format named in an 'F' message's text, fields without offsets. A
// problem is returned in `error` (empty when fine), without a place.
ULogFormat parse_ulog_format(std::string_view text, std::string& error);

// Sets every field's offset and element size and every format's size and
// logged size, nested types first. A field of an unknown type, a circular
// nesting or a format larger than a message can be is returned as the
// index of the format and the problem (index formats.size() when fine).
std::size_t lay_out_ulog_formats(std::vector<ULogFormat>& formats, std::string& error);

}  // namespace cubecal::io::detail
