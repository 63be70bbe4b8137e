// A file read by byte ranges (pread), for readers that take one record of a
// log at a time instead of mapping the whole file.
#pragma once
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "cubecal/error.hpp"

namespace cubecal::io::detail {

class RecordFile {
 public:
  explicit RecordFile(const std::string& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw InputError(path, 0, 0, std::string("cannot open: ") + std::strerror(errno), "check the path");
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
      ::close(fd_);
      throw InputError(path, 0, 0, "not a regular file", "give the log's file");
    }
    size_ = static_cast<std::size_t>(st.st_size);
  }
  RecordFile(const RecordFile&) = delete;
  RecordFile& operator=(const RecordFile&) = delete;
  ~RecordFile() { ::close(fd_); }

  std::size_t size() const noexcept { return size_; }

  // Bytes [pos, pos + n) into `out`, cut at the end of the file.
  void read(std::size_t pos, std::size_t n, std::string& out) const {
    n = pos >= size_ ? 0 : std::min(n, size_ - pos);
    out.resize(n);
    std::size_t got = 0;
    while (got < n) {
      const ssize_t r = ::pread(fd_, out.data() + got, n - got, static_cast<off_t>(pos + got));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) throw InputError(path_, 0, 0, std::string("read error: ") + std::strerror(r < 0 ? errno : EIO));
      got += static_cast<std::size_t>(r);
    }
  }

  // The little-endian unsigned integer of `bytes` bytes at `pos`, or
  // nullopt-like `fallback` beyond the end.
  std::uint64_t le(std::size_t pos, std::size_t bytes, std::uint64_t fallback) const {
    if (pos > size_ || size_ - pos < bytes) return fallback;
    std::string b;
    read(pos, bytes, b);
    std::uint64_t v = 0;
    for (std::size_t k = bytes; k-- > 0;) v = v << 8 | static_cast<unsigned char>(b[k]);
    return v;
  }

 private:
  std::string path_;
  int fd_ = -1;
  std::size_t size_ = 0;
};

}  // namespace cubecal::io::detail
