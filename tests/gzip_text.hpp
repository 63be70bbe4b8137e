// Test support: bytes compressed into one gzip member with zlib (the tests
// that build gzip inputs: hostile input, streamed formats, the corpus).
#pragma once
#include <zlib.h>

#include <string>

namespace cubecal::test {

// `text` as one gzip member at zlib `level` (1 fast .. 9 small); empty if zlib fails.
inline std::string gzip(const std::string& text, int level = 9) {
  z_stream zs{};
  if (deflateInit2(&zs, level, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK) return {};
  std::string out(deflateBound(&zs, text.size()), '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  zs.avail_in = static_cast<uInt>(text.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  deflate(&zs, Z_FINISH);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

}  // namespace cubecal::test
