// The data of a ROS 1 bag chunk, decompressed: "none", "bz2" (libbz2) or
// "lz4" (the LZ4 frame format roslz4 writes; liblz4). Used by ros1_bag.cpp.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

#include "ros1_record.hpp"

namespace cubecal::io::detail {

// Exactly `size` bytes (the chunk's "size" field) from `data`, or a
// bag_error at `pos`: an unknown compression, corrupt compressed data, or a
// size that differs from what the data inflate to. The output grows with
// what is actually decompressed, so a corrupt size field cannot make it
// reserve gigabytes up front.
std::string decompress_chunk(std::string_view compression, std::string_view data, std::size_t size, const BagPlace& at,
                             std::size_t pos);

}  // namespace cubecal::io::detail
