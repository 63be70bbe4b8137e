// libFuzzer target: the gzip path of the readers. The input is a file (gzip
// or not, recognised by its magic bytes as cubecal does); FileBuffer::open
// inflates it and the text is parsed as a table. Allocations stay bounded by
// what was decompressed, whatever the stream's trailer claims (libFuzzer's
// -malloc_limit_mb reports a larger one as a finding).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "cubecal/io/delimited_reader.hpp"
#include "../src/io/detail/file_buffer.hpp"
#include "error_check.hpp"
#include "memory_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cubecal;
  const fuzz::MemoryFile file(std::string_view(reinterpret_cast<const char*>(data), size));
  fuzz::expect_clean([&] {
    const io::FileBuffer buf = io::FileBuffer::open(file.path());
    io::TableOptions opt;
    opt.threads = 1;
    (void)io::parse_table(buf.view(), file.path(), opt);
  });
  return 0;
}
