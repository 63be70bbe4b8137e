#include "ros1_chunk.hpp"

#include <bzlib.h>
#include <lz4frame.h>

#include <algorithm>
#include <memory>

namespace cubecal::io::detail {

namespace {

// The next size of an output buffer that must end at `size` bytes.
std::size_t grown(std::size_t have, std::size_t size) {
  return std::min(size, std::max<std::size_t>(have * 2, 1u << 16));
}

[[noreturn]] void size_mismatch(const BagPlace& at, std::size_t pos, const char* kind, std::size_t got,
                                std::size_t size) {
  bag_error(at, pos,
            std::string(kind) + " chunk inflates to " + (got > size ? "more than " : "") + std::to_string(got) +
                " bytes, its header says " + std::to_string(size));
}

std::string bunzip(std::string_view data, std::size_t size, const BagPlace& at, std::size_t pos) {
  bz_stream z{};
  if (BZ2_bzDecompressInit(&z, 0, 0) != BZ_OK) bag_error(at, pos, "cannot start the bz2 decompressor");
  const std::unique_ptr<bz_stream, int (*)(bz_stream*)> guard(&z, BZ2_bzDecompressEnd);
  std::string out;
  std::size_t done = 0;
  std::size_t in_done = 0;
  for (;;) {
    if (done == out.size()) {
      if (out.size() == size) {
        // Full: the stream must end here, with no byte more.
        char probe = 0;
        z.next_out = &probe;
        z.avail_out = 1;
      } else {
        out.resize(grown(out.size(), size));
      }
    }
    const bool probing = done == size;
    if (!probing) {
      z.next_out = out.data() + done;
      z.avail_out = static_cast<unsigned>(std::min<std::size_t>(out.size() - done, 1u << 30));
    }
    const std::size_t in_left = data.size() - in_done;
    z.next_in = const_cast<char*>(data.data() + in_done);
    z.avail_in = static_cast<unsigned>(std::min<std::size_t>(in_left, 1u << 30));
    const unsigned avail_out = z.avail_out;
    const unsigned avail_in = z.avail_in;
    const int rc = BZ2_bzDecompress(&z);
    const std::size_t produced = avail_out - z.avail_out;
    in_done += avail_in - z.avail_in;
    if (rc != BZ_OK && rc != BZ_STREAM_END)
      bag_error(at, pos, "corrupt bz2 chunk data (libbz2 error " + std::to_string(rc) + ")");
    if (probing && produced > 0) size_mismatch(at, pos, "bz2", size + 1, size);
    if (!probing) done += produced;
    if (rc == BZ_STREAM_END) break;
    if (produced == 0 && z.avail_in == avail_in)
      bag_error(at, pos,
                in_done == data.size() ? "bz2 chunk data end before the compressed stream does"
                                       : "corrupt bz2 chunk data (no progress)");
  }
  if (done != size) size_mismatch(at, pos, "bz2", done, size);
  out.resize(done);
  return out;
}

std::string unlz4(std::string_view data, std::size_t size, const BagPlace& at, std::size_t pos) {
  LZ4F_dctx* ctx = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION)))
    bag_error(at, pos, "cannot start the LZ4 decompressor");
  const std::unique_ptr<LZ4F_dctx, LZ4F_errorCode_t (*)(LZ4F_dctx*)> guard(ctx, LZ4F_freeDecompressionContext);
  std::string out;
  std::size_t done = 0;
  std::size_t in_done = 0;
  char probe = 0;
  for (;;) {
    if (done == out.size() && out.size() < size) out.resize(grown(out.size(), size));
    const bool probing = done == size;
    char* dst = probing ? &probe : out.data() + done;
    std::size_t dst_size = probing ? 1 : out.size() - done;
    std::size_t src_size = data.size() - in_done;
    const std::size_t hint = LZ4F_decompress(ctx, dst, &dst_size, data.data() + in_done, &src_size, nullptr);
    if (LZ4F_isError(hint)) bag_error(at, pos, std::string("corrupt LZ4 chunk data (") + LZ4F_getErrorName(hint) + ")");
    in_done += src_size;
    if (probing && dst_size > 0) size_mismatch(at, pos, "lz4", size + 1, size);
    if (!probing) done += dst_size;
    if (hint == 0) break;  // the frame is complete
    if (src_size == 0 && dst_size == 0)
      bag_error(
          at, pos,
          in_done == data.size() ? "LZ4 chunk data end before the frame does" : "corrupt LZ4 chunk data (no progress)");
  }
  if (done != size) size_mismatch(at, pos, "lz4", done, size);
  out.resize(done);
  return out;
}

}  // namespace

std::string decompress_chunk(std::string_view compression, std::string_view data, std::size_t size, const BagPlace& at,
                             std::size_t pos) {
  if (compression == "none") {
    if (data.size() != size)
      bag_error(at, pos,
                "uncompressed chunk holds " + std::to_string(data.size()) + " bytes, its header says " +
                    std::to_string(size));
    return std::string(data);
  }
  if (compression == "bz2") return bunzip(data, size, at, pos);
  if (compression == "lz4") return unlz4(data, size, at, pos);
  bag_error(at, pos, "chunk compression '" + std::string(compression) + "' is not none, bz2 or lz4");
}

}  // namespace cubecal::io::detail
