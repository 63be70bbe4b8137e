#include "mcap_chunk.hpp"

#include <zstd.h>

#include <algorithm>
#include <memory>

#include "ros1_chunk.hpp"

namespace cubecal::io::detail {

namespace {

std::string unzstd(std::string_view data, std::size_t size, const BagPlace& at, std::size_t pos) {
  const std::unique_ptr<ZSTD_DCtx, std::size_t (*)(ZSTD_DCtx*)> ctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
  if (!ctx) bag_error(at, pos, "cannot start the zstd decompressor");
  std::string out;
  std::size_t done = 0;
  ZSTD_inBuffer in{data.data(), data.size(), 0};
  std::size_t last = 0;  // 0: the last frame is complete
  char probe = 0;
  while (in.pos < in.size) {
    if (done == out.size() && out.size() < size)
      out.resize(std::min(size, std::max<std::size_t>(out.size() * 2, 1u << 16)));
    const bool probing = done == size;
    ZSTD_outBuffer o{probing ? &probe : out.data() + done, probing ? 1 : out.size() - done, 0};
    const std::size_t before = in.pos;
    last = ZSTD_decompressStream(ctx.get(), &o, &in);
    if (ZSTD_isError(last))
      bag_error(at, pos, std::string("corrupt zstd chunk data (") + ZSTD_getErrorName(last) + ")");
    if (probing && o.pos > 0)
      bag_error(at, pos,
                "zstd chunk inflates to more than " + std::to_string(size) + " bytes, its header says " +
                    std::to_string(size));
    if (!probing) done += o.pos;
    if (o.pos == 0 && in.pos == before) bag_error(at, pos, "corrupt zstd chunk data (no progress)");
  }
  // The decoder may hold output it has not flushed yet.
  while (last != 0 && done < size) {
    ZSTD_inBuffer none{nullptr, 0, 0};
    ZSTD_outBuffer o{out.data() + done, out.size() - done, 0};
    last = ZSTD_decompressStream(ctx.get(), &o, &none);
    if (ZSTD_isError(last))
      bag_error(at, pos, std::string("corrupt zstd chunk data (") + ZSTD_getErrorName(last) + ")");
    if (o.pos == 0) break;
    done += o.pos;
    if (done == out.size() && out.size() < size)
      out.resize(std::min(size, std::max<std::size_t>(out.size() * 2, 1u << 16)));
  }
  if (last != 0) bag_error(at, pos, "zstd chunk data end before the compressed frame does");
  if (done != size)
    bag_error(at, pos,
              "zstd chunk inflates to " + std::to_string(done) + " bytes, its header says " + std::to_string(size));
  out.resize(done);
  return out;
}

}  // namespace

std::string decompress_mcap_chunk(std::string_view compression, std::string_view data, std::size_t size,
                                  const BagPlace& at, std::size_t pos) {
  if (compression.empty()) return decompress_chunk("none", data, size, at, pos);
  if (compression == "lz4") return decompress_chunk("lz4", data, size, at, pos);
  if (compression == "zstd") return unzstd(data, size, at, pos);
  bag_error(at, pos, "chunk compression '" + std::string(compression) + "' is not none, zstd or lz4");
}

}  // namespace cubecal::io::detail
