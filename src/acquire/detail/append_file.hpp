// A file written only at its end through a buffer: write() to the kernel
// by flush(), fsync by sync(). Every failure is a WriteFailure naming the
// file. The CRC-32 of everything written is kept as it goes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace cubecal::acquire::detail {

class AppendFile {
 public:
  // Creates `path` (refused when it exists: exclusive) and fsyncs its
  // directory so that the name survives a power loss; with `existing`,
  // opens the file that is there for appending (its CRC is then not kept),
  // which must be a regular file. A symbolic link is never followed
  // (O_NOFOLLOW): ELOOP.
  AppendFile(std::string path, bool existing = false, std::size_t buffer = 1 << 20);
  ~AppendFile();
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;

  void append(std::string_view s) {
    buf_.append(s);
    if (buf_.size() >= limit_) flush();
  }
  std::string& buffer() noexcept { return buf_; }  // append to it, then call maybe_flush()
  void maybe_flush() {
    if (buf_.size() >= limit_) flush();
  }
  void flush();
  void sync();
  void close();

  const std::string& path() const noexcept { return path_; }
  std::size_t written() const noexcept { return written_; }             // bytes given to the kernel
  std::size_t size() const noexcept { return written_ + buf_.size(); }  // including the buffer
  std::uint32_t crc() const noexcept { return crc_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::string buf_;
  std::size_t limit_;
  std::size_t written_ = 0;
  std::uint32_t crc_ = 0;
};

// fsync of a directory (its entries); a WriteFailure naming it on failure.
// A symbolic link at `dir` is followed only with `follow_link` (the
// recording directory the user named; never a segment's).
void sync_directory(const std::string& dir, bool follow_link = false);

// Opens `path` with `flags` | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC and checks
// it is a regular file (a FIFO or a device is closed unread); -1 with errno
// set (ELOOP for a symbolic link, EINVAL for anything but a regular file).
int open_regular(const std::string& path, int flags, int mode = 0644);

}  // namespace cubecal::acquire::detail
