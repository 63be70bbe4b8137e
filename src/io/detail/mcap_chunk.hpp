// The records of an MCAP chunk, decompressed: "" (none), "zstd" (libzstd)
// or "lz4" (the LZ4 frame format; liblz4). Used by mcap.cpp.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

#include "ros1_record.hpp"

namespace cubecal::io::detail {

// Exactly `size` bytes (the chunk's uncompressed_size) from `data`, or a
// bag_error at `pos`: an unknown compression, corrupt compressed data, or a
// size that differs from what the data inflate to. The output grows with
// what is actually decompressed, never reserved from the size field.
std::string decompress_mcap_chunk(std::string_view compression, std::string_view data, std::size_t size,
                                  const BagPlace& at, std::size_t pos);

}  // namespace cubecal::io::detail
